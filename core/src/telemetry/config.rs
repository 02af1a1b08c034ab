//! The monitor configuration as telemetry frames: the host sends the
//! mechanism first, so the firmware needs no table of mechanisms compiled in
//! and replays any mechanism of its monitor's joint count (at most
//! [`MAX_JOINTS`]).
//!
//! ```text
//! input = ConfigHeader ‖ JointFrame × joints ‖ Sample<joints> × samples
//! ```
//!
//! Every frame is the core's telemetry frame (postcard ‖ CRC-32C, COBS,
//! `0x00`). The frames carry the `f32` values that the host's conversion of a
//! mechanism file (`deploywatch_sim::monitor_config`) feeds to the core's
//! constructors (`Spring::tape`, `Curve::new`, `MonitorConfig::new`), so the
//! firmware builds the same [`MonitorConfig`] from them: the host checks that
//! [`ConfigHeader::config`] of the frames equals its own conversion before
//! every replay. Everything else of the configuration is the core's default
//! tuning, the same code on both sides.

use crate::monitor::latch::PhysicalLatch;
use crate::monitor::latch_margin::Engagement;
use crate::monitor::observer::FrictionPrior;
use crate::monitor::{JointConfig, MonitorConfig};
use crate::physics::chain::Panel;
use crate::physics::spring::{Curve, Spring, TapePoints};
use crate::physics::spring::{CurveError, Fold, Interp, MAX_KNOTS};
use serde::{Deserialize, Serialize};

/// The most joints the configuration and sample frames carry, and so the
/// most a firmware's monitor may have. The joint count itself is the
/// firmware's: it builds one `Monitor<N>` (`N` in `1..=MAX_JOINTS`, a const
/// generic of [`super::replay::MonitorStore`]) and refuses a configuration of
/// another count ([`super::replay::Error::JointCount`]). It sizes the
/// replay's frame buffers.
pub const MAX_JOINTS: usize = crate::monitor::rollout::ROLLOUT_MAX_JOINTS;

/// Version of the replay's frames: the configuration and the status frames
/// the firmware answers with (a field added to either is a new version);
/// the firmware refuses another.
pub const CONFIG_VERSION: u8 = 5;

/// The first frame of a replay input.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ConfigHeader {
    /// [`CONFIG_VERSION`].
    pub version: u8,
    /// Joints of the mechanism, 1 to [`MAX_JOINTS`] (a firmware takes its
    /// monitor's count); as many [`JointFrame`]s follow.
    pub joints: u8,
    /// The deployment's deadline (`MarginConfig::deadline_s`) \[s\].
    pub deadline_s: f32,
    /// The latch as built of every joint without its own
    /// ([`JointFrame::physical`]; `LatchConfig::physical`), `None` for the
    /// ideal latch.
    pub latch: Option<PhysicalLatch>,
}

/// Tabulated knots of a curve spring branch.
#[derive(Clone, Copy, Debug, PartialEq, Default, Serialize, Deserialize)]
pub struct Knots {
    /// Knots used (at most [`MAX_KNOTS`]).
    pub len: u8,
    /// Angles \[deg\].
    pub x: [f32; MAX_KNOTS],
    /// Moments per hinge [N·m].
    pub y: [f32; MAX_KNOTS],
}

impl Knots {
    /// The knots of `points`; `None` for more than [`MAX_KNOTS`].
    pub fn new(points: &[(f32, f32)]) -> Option<Self> {
        if points.len() > MAX_KNOTS {
            return None;
        }
        let mut k = Knots {
            len: points.len() as u8,
            ..Knots::default()
        };
        for (i, &(x, y)) in points.iter().enumerate() {
            k.x[i] = x;
            k.y[i] = y;
        }
        Some(k)
    }

    fn curve(&self, interp: Interp) -> Result<Curve<f32>, CurveError> {
        let n = usize::from(self.len).min(MAX_KNOTS);
        let mut pts = [(0.0f32, 0.0f32); MAX_KNOTS];
        for (i, p) in pts.iter_mut().enumerate().take(n) {
            *p = (self.x[i], self.y[i]);
        }
        Curve::new(&pts[..n], interp)
    }
}

/// A joint's spring, as the mechanism file gives it.
// The curve variant's knots are inline: no heap to box them in, and one
// value at a time is decoded.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Copy, Debug, PartialEq, Default, Serialize, Deserialize)]
pub enum SpringFrame {
    /// No spring.
    #[default]
    None,
    /// `Spring::Linear`.
    Linear {
        /// Per hinge [N·m].
        preload_nm: f32,
        /// Per hinge [N·m/rad].
        stiffness_nm_per_rad: f32,
        /// Hinges.
        count: f32,
    },
    /// `Spring::tape(points, count)` (seed 001 tape spring).
    Tape {
        /// The type's points.
        points: TapeFrame,
        /// Hinges.
        count: f32,
    },
    /// `Spring::Curve` from tabulated branches.
    Curve {
        /// Akima (true) or linear (false) interpolation.
        akima: bool,
        /// Unfolding branch.
        unfold: Knots,
        /// Folding branch, `None` for no hysteresis.
        fold: Option<Knots>,
        /// Hinges.
        count: f32,
    },
}

/// `TapePoints<f32>` on the wire.
#[derive(Clone, Copy, Debug, PartialEq, Default, Serialize, Deserialize)]
pub struct TapeFrame {
    /// Point A (deg, N·m).
    pub a: (f32, f32),
    /// Point B.
    pub b: (f32, f32),
    /// Point D.
    pub d: (f32, f32),
    /// Moment at 90° [N·m].
    pub m_90: f32,
    /// Moment at 180° [N·m].
    pub c_180: f32,
}

impl From<&TapePoints<f32>> for TapeFrame {
    fn from(p: &TapePoints<f32>) -> Self {
        TapeFrame {
            a: p.a,
            b: p.b,
            d: p.d,
            m_90: p.m_90,
            c_180: p.c_180,
        }
    }
}

impl SpringFrame {
    /// The core's spring.
    pub fn spring(&self) -> Result<Spring<f32>, CurveError> {
        Ok(match *self {
            SpringFrame::None => Spring::None,
            SpringFrame::Linear {
                preload_nm,
                stiffness_nm_per_rad,
                count,
            } => Spring::Linear {
                preload_nm,
                stiffness_nm_per_rad,
                count,
            },
            SpringFrame::Tape { points, count } => {
                let p = TapePoints {
                    a: points.a,
                    b: points.b,
                    d: points.d,
                    m_90: points.m_90,
                    c_180: points.c_180,
                };
                Spring::tape(&p, count)?
            }
            SpringFrame::Curve {
                akima,
                unfold,
                fold,
                count,
            } => {
                let interp = if akima { Interp::Akima } else { Interp::Linear };
                Spring::Curve {
                    unfold: unfold.curve(interp)?,
                    fold: match fold {
                        None => Fold::SameAsUnfold,
                        Some(f) => Fold::Curve(f.curve(interp)?),
                    },
                    count,
                }
            }
        })
    }
}

/// Fields of the core's `FrictionPrior` (all `f32`): when the core's prior
/// changes, this, [`JointFrame::to_config`] and the host's
/// `deploywatch_sim::replay::joint_frame` change with it (the host's equality
/// check before every replay fails until they do).
pub(crate) const PRIOR_FIELDS: usize = 4;

/// One joint and the panel it drives: frames 1 to `joints` of the input.
#[derive(Clone, Copy, Debug, PartialEq, Default, Serialize, Deserialize)]
pub struct JointFrame {
    /// Panel length \[m\].
    pub length_m: f32,
    /// Panel mass \[kg\].
    pub mass_kg: f32,
    /// Panel centre of mass from the hinge \[m\].
    pub com_m: f32,
    /// Panel inertia about its centre of mass [kg·m²].
    pub inertia_kgm2: f32,
    /// `JointConfig::stowed_deg`.
    pub stowed_deg: f32,
    /// The spring.
    pub spring: SpringFrame,
    /// `JointConfig::capture_deg`.
    pub capture_deg: f32,
    /// `FrictionPrior` fields in declaration order: Coulomb mean and sd
    /// [N·m], viscous mean and sd [N·m·s/rad].
    pub prior: [f32; PRIOR_FIELDS],
    /// `JointConfig::latch` (`Engagement`, all 0 for the ideal latch):
    /// engagement energy \[J\] (three plain `f32` fields rather than an array:
    /// one deserializer fewer in flash).
    pub latch_energy_j: f32,
    /// Its crest \[rad\].
    pub latch_crest_rad: f32,
    /// Its entry ramp's width \[rad\].
    pub latch_ramp_rad: f32,
    /// `JointConfig::physical`: the joint's own physical latch (`None`:
    /// the header's [`ConfigHeader::latch`], and with none there the ideal
    /// latch).
    pub physical: Option<PhysicalLatch>,
}

/// Fields of the core's `Engagement` (all `f32`): when it changes, the
/// `latch_*` fields of [`JointFrame`], [`JointFrame::to_config`] and the
/// host's `deploywatch_sim::replay::joint_frame` change with it.
pub(crate) const LATCH_FIELDS: usize = 3;

impl JointFrame {
    /// The panel and joint configuration.
    pub fn to_config(&self) -> Result<(Panel<f32>, JointConfig), CurveError> {
        let [coulomb_nm, coulomb_sd_nm, viscous_nms, viscous_sd_nms] = self.prior;
        Ok((
            Panel {
                length_m: self.length_m,
                mass_kg: self.mass_kg,
                com_m: self.com_m,
                inertia_kgm2: self.inertia_kgm2,
            },
            JointConfig {
                stowed_deg: self.stowed_deg,
                spring: self.spring.spring()?,
                capture_deg: self.capture_deg,
                prior: FrictionPrior {
                    coulomb_nm,
                    coulomb_sd_nm,
                    viscous_nms,
                    viscous_sd_nms,
                },
                latch: Engagement {
                    energy_j: self.latch_energy_j,
                    crest_rad: self.latch_crest_rad,
                    ramp_rad: self.latch_ramp_rad,
                },
                physical: self.physical,
            },
        ))
    }
}

impl ConfigHeader {
    /// The monitor configuration of this header and its `N` joint frames:
    /// the core's default tuning with these panels, joints, deadline and
    /// latch.
    /// `None` when `N` is not the header's joint count; the error of a
    /// spring curve the core rejects.
    pub fn config<const N: usize>(
        &self,
        joints: &[JointFrame; N],
    ) -> Option<Result<MonitorConfig<N>, CurveError>> {
        if usize::from(self.joints) != N {
            return None;
        }
        Some(build(self, joints))
    }
}

fn build<const N: usize>(
    header: &ConfigHeader,
    frames: &[JointFrame; N],
) -> Result<MonitorConfig<N>, CurveError> {
    // Placeholders, all overwritten (a spring of `None` always builds).
    let first = JointFrame::default().to_config()?;
    let mut panels = [first.0; N];
    let mut joints = [first.1; N];
    for (i, f) in frames.iter().enumerate() {
        let (p, j) = f.to_config()?;
        panels[i] = p;
        joints[i] = j;
    }
    let mut config = MonitorConfig::new(panels, joints);
    config.margin.deadline_s = header.deadline_s;
    config.latch.physical = header.latch;
    Ok(config)
}

/// Largest frame of a [`ConfigHeader`], `0x00` included \[bytes\]
/// (payload: 1 + 1 + 4, and the latch: 1 + 4·4 + its lock 1).
pub const CONFIG_HEADER_FRAME_MAX: usize = framed(24);

/// Largest postcard payload of a [`JointFrame`]: five `f32` of panel and
/// stowed angle (20), the spring (tag 1 + count 4 + the curve variant's
/// flag 1, knots 1 + 2·4·[`MAX_KNOTS`] and optional knots 1 + the same),
/// the capture angle (4), the prior and the latch (4 each), and the
/// joint's physical latch (1 + 4·4 + its lock 1).
pub(crate) const JOINT_FRAME_PAYLOAD_MAX: usize = 20
    + (1 + 4 + 1 + 2 * (1 + 8 * MAX_KNOTS) + 1)
    + 4
    + 4 * PRIOR_FIELDS
    + 4 * LATCH_FIELDS
    + (1 + 4 * 4 + 1);

/// Largest frame of a [`JointFrame`], `0x00` included \[bytes\].
pub const JOINT_FRAME_MAX: usize = framed(JOINT_FRAME_PAYLOAD_MAX);

/// The core's framing overhead (see `crate::telemetry`).
const fn framed(payload: usize) -> usize {
    let with_crc = payload + 4;
    with_crc + with_crc.div_ceil(254) + 1
}
