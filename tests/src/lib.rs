//! Shared helpers of the cross-crate tests: where the bundled data lives.
#![deny(missing_docs)]

use std::path::PathBuf;

/// The repository root.
pub fn repo_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map(|p| p.to_path_buf())
        .unwrap_or_default()
}

/// `data/` in the repository (copies of `shared/`, see `data/README.md`).
pub fn data_dir() -> PathBuf {
    repo_root().join("data")
}

pub mod hidden_torque;
