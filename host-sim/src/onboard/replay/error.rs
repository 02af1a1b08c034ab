//! Why a replay failed, and the first difference of two status streams.

/// Why a replay failed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ReplayError {
    /// The inputs cannot be replayed (files, joint counts, configuration).
    #[error("{0}")]
    Input(String),
    /// QEMU or the firmware ELF is missing.
    #[error("{0}")]
    Setup(String),
    /// The firmware (or QEMU) failed on a valid input.
    #[error("{0}")]
    Target(String),
    /// The two sides' statuses differ.
    #[error("{0}")]
    Mismatch(Mismatch),
}

/// The first difference of two status streams.
#[derive(Clone, Debug, PartialEq)]
pub struct Mismatch {
    /// 0-based status frame.
    pub frame: usize,
    /// 1-based joint, `None` for a field of the whole status (or for a
    /// difference of length or of bytes only).
    pub joint: Option<usize>,
    /// The field (`t_s`, `coulomb_nm`, ...) or what differs.
    pub field: String,
    /// The value on the host.
    pub host: String,
    /// The value on the target.
    pub target: String,
}

impl std::fmt::Display for Mismatch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "status frame {}", self.frame)?;
        if let Some(j) = self.joint {
            write!(f, ", joint {j}")?;
        }
        write!(
            f,
            ", {}: host {}, target {}",
            self.field, self.host, self.target
        )
    }
}
