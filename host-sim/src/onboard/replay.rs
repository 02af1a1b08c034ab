//! Replay of a recorded run through the on-board monitor, on the host or on
//! the example firmware under QEMU (`deploywatch replay`), and the check that
//! both give bit-identical statuses.
//!
//! ```text
//! Mechanism ──config_frames──┐
//! Run ───────sample frames───┴─> input ──host: Monitor<N>::update (f32)──> status frames
//!                                      └─QEMU: firmware (Cortex-M4F)─────> status frames ── compare
//! ```
//!
//! The input is the firmware's protocol (`deploywatch_core::telemetry::replay`): the
//! monitor configuration as frames ([`config_frames`]), then one
//! [`Sample<N>`] frame per sample; the output one [`Status<N>`] frame per
//! sample. Frames are the core's telemetry frames
//! ([`deploywatch_core::telemetry`]). The host's statuses come from the
//! simulator's own path ([`monitor_config`]
//! and [`Monitor::update_and_predict`]); the configuration frames are checked to build
//! the very same [`MonitorConfig`] before any replay, so a difference of the
//! two sides is one of the target, never of the configuration.
//!
//! Everything after the frames works on [`StatusRow`]s, which hold any joint
//! count: the status CSV ([`write_status_csv`]), the per-joint
//! [`summary`], the [`plot()`] and the field-by-field [`compare`].

use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use deploywatch_core::monitor::{JointStatus, Monitor, MonitorConfig, Sample, Status};
use deploywatch_core::spring::Interp;
use deploywatch_core::telemetry;
use deploywatch_core::telemetry::config::{
    ConfigHeader, JointFrame, Knots, SpringFrame, TapeFrame, CONFIG_VERSION,
};

use crate::data::run::Run;
use crate::model::mechanism::{with_joints, Mechanism, SpringSpec};
use crate::onboard::monitor_config::{monitor_config, samples, spring_f32};
use crate::report::plot::{self, Mark, Panel, Series};

/// The QEMU program the firmware runs on.
pub const QEMU: &str = "qemu-system-arm";

/// What to run when the firmware ELF or QEMU is missing.
pub(crate) const SETUP_HINT: &str =
    "run scripts/embedded-toolchain.sh (once per machine), then scripts/firmware.sh build";

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

/// One status of any joint count, as the rest of this module uses it.
#[derive(Clone, Debug, PartialEq)]
pub struct StatusRow {
    /// Time of the sample \[s\].
    pub t_s: f32,
    /// Samples seen.
    pub samples: u32,
    /// Per joint.
    pub joints: Vec<JointStatus>,
}

impl<const N: usize> From<&Status<N>> for StatusRow {
    fn from(s: &Status<N>) -> Self {
        StatusRow {
            t_s: s.t_s,
            samples: s.samples,
            joints: s.joints.to_vec(),
        }
    }
}

/// A run ready to replay: the input frames and the host's statuses.
#[derive(Clone, Debug)]
pub struct Prepared {
    /// Joints.
    pub joints: usize,
    /// Samples.
    pub samples: usize,
    /// The firmware's input: configuration frames, then sample frames.
    pub input: Vec<u8>,
    /// The host's `f32` monitor run, as status frames.
    pub host_frames: Vec<u8>,
    /// The same, decoded.
    pub host: Vec<StatusRow>,
}

/// Loads a run for the monitor (missing samples allowed, as `NaN`).
pub fn load_run(path: &Path) -> Result<Run, ReplayError> {
    let opts = crate::data::run::ReadOptions {
        allow_missing: true,
    };
    Run::load_with(path, opts).map_err(|e| ReplayError::Input(e.to_string()))
}

/// The firmware's [`JointFrame`] of joint `j` (0-based) of `mech`: the same
/// `f32` values that [`monitor_config`] gives the core's constructors.
pub fn joint_frame(mech: &Mechanism, j: usize) -> Result<JointFrame, ReplayError> {
    let (p, joint) = match (mech.panels.get(j), mech.joints.get(j)) {
        (Some(p), Some(joint)) => (p, joint),
        _ => {
            return Err(ReplayError::Input(format!(
                "{}: no joint {}",
                mech.name,
                j + 1
            )))
        }
    };
    let curve_err =
        |e| ReplayError::Input(format!("{}: joint {}: spring curve: {e}", mech.name, j + 1));
    // The capture angle is derived by the host's conversion; take it from there.
    let (_, capture_deg) = spring_f32(&joint.spring).map_err(curve_err)?;
    let knots = |pts: &[(f64, f64)]| {
        let p: Vec<(f32, f32)> = pts.iter().map(|&(x, y)| (x as f32, y as f32)).collect();
        Knots::new(&p).ok_or_else(|| {
            ReplayError::Input(format!(
                "{}: joint {}: too many spring knots",
                mech.name,
                j + 1
            ))
        })
    };
    let spring = match &joint.spring {
        SpringSpec::Linear {
            preload_nm,
            stiffness_nm_per_rad,
            count,
        } => SpringFrame::Linear {
            preload_nm: *preload_nm as f32,
            stiffness_nm_per_rad: *stiffness_nm_per_rad as f32,
            count: *count as f32,
        },
        SpringSpec::Tape { points, count, .. } => SpringFrame::Tape {
            points: TapeFrame {
                a: (points.a.0 as f32, points.a.1 as f32),
                b: (points.b.0 as f32, points.b.1 as f32),
                d: (points.d.0 as f32, points.d.1 as f32),
                m_90: points.m_90 as f32,
                c_180: points.c_180 as f32,
            },
            count: *count as f32,
        },
        SpringSpec::Curve {
            unfold,
            fold,
            interp,
            count,
        } => SpringFrame::Curve {
            akima: *interp == Interp::Akima,
            unfold: knots(unfold)?,
            fold: fold.as_deref().map(knots).transpose()?,
            count: *count as f32,
        },
    };
    let latch = crate::onboard::monitor_config::engagement(mech, j);
    let spread = crate::onboard::monitor_config::PriorSpread::default();
    Ok(JointFrame {
        length_m: p.length_m as f32,
        mass_kg: p.mass_kg as f32,
        com_m: p.com_m as f32,
        inertia_kgm2: p.inertia_kgm2 as f32,
        stowed_deg: joint.stowed_deg as f32,
        spring,
        capture_deg: capture_deg as f32,
        // The default spread of the prior, as `monitor_config` takes it.
        prior: [
            joint.friction.coulomb_nm as f32,
            spread.coulomb_sd_nm as f32,
            joint.friction.viscous_nms as f32,
            spread.viscous_sd_nms as f32,
        ],
        latch_energy_j: latch.energy_j,
        latch_crest_rad: latch.crest_rad,
        latch_ramp_rad: latch.ramp_rad,
        physical: crate::onboard::monitor_config::joint_physical_latch(mech, j),
    })
}

fn encode_into<T: serde::Serialize>(
    value: &T,
    out: &mut Vec<u8>,
    what: &str,
) -> Result<(), ReplayError> {
    let mut buf = [0u8; 2048];
    let frame = telemetry::encode(value, &mut buf)
        .map_err(|e| ReplayError::Input(format!("{what}: {e}")))?;
    out.extend_from_slice(frame);
    Ok(())
}

/// The configuration frames of `mech` for a monitor of `N` joints, after
/// checking that they build the same [`MonitorConfig`] as the host's
/// conversion `config`.
pub fn config_frames<const N: usize>(
    mech: &Mechanism,
    config: &MonitorConfig<N>,
) -> Result<Vec<u8>, ReplayError> {
    let header = ConfigHeader {
        version: CONFIG_VERSION,
        joints: N as u8,
        deadline_s: mech.duration_s as f32,
        latch: config.latch.physical,
    };
    let mut joints = Vec::with_capacity(N);
    for j in 0..N {
        joints.push(joint_frame(mech, j)?);
    }
    let joints: [JointFrame; N] = joints
        .try_into()
        .map_err(|_| ReplayError::Input(format!("{}: not {N} joints", mech.name)))?;
    match header.config(&joints) {
        Some(Ok(c)) if c == *config => {}
        _ => {
            return Err(ReplayError::Input(format!(
                "{}: the configuration frames do not rebuild the host's monitor configuration \
                 (core/src/telemetry/config.rs and host-sim/src/onboard/replay.rs are out of step \
                 with deploywatch_sim::onboard::monitor_config)",
                mech.name
            )))
        }
    }
    let mut out = Vec::new();
    encode_into(&header, &mut out, "configuration header")?;
    for (j, f) in joints.iter().enumerate() {
        encode_into(f, &mut out, &format!("joint {} frame", j + 1))?;
    }
    Ok(out)
}

/// The monitor's configuration of `mech` and the samples of `run` for a
/// monitor of `N` joints (what every replay and the serial link start from).
pub(crate) fn config_and_samples<const N: usize>(
    mech: &Mechanism,
    run: &Run,
) -> Result<(MonitorConfig<N>, Vec<Sample<N>>), ReplayError> {
    let config =
        monitor_config::<N>(mech).map_err(|e| ReplayError::Input(format!("{}: {e}", mech.name)))?;
    let n = run.joints();
    let samples = samples::<N>(run)
        .ok_or_else(|| ReplayError::Input(format!("the run has {n} joints, the mechanism {N}")))?;
    Ok((config, samples))
}

fn prepare_n<const N: usize>(mech: &Mechanism, run: &Run) -> Result<Prepared, ReplayError> {
    let (config, samples) = config_and_samples::<N>(mech, run)?;
    let mut input = config_frames::<N>(mech, &config)?;
    for (i, s) in samples.iter().enumerate() {
        encode_into(s, &mut input, &format!("sample {i}"))?;
    }
    let mut monitor =
        Monitor::new(&config).map_err(|e| ReplayError::Input(format!("{}: {e}", mech.name)))?;
    let mut host_frames = Vec::new();
    let mut host = Vec::with_capacity(samples.len());
    for (i, s) in samples.iter().enumerate() {
        let status = monitor.update_and_predict(s);
        encode_into(&status, &mut host_frames, &format!("status {i}"))?;
        host.push(StatusRow::from(&status));
    }
    Ok(Prepared {
        joints: N,
        samples: samples.len(),
        input,
        host_frames,
        host,
    })
}

/// Checks that `run` is of `mech` (its `mechanism` metadata, when given)
/// and returns the mechanism's joint count.
pub(crate) fn run_of(mech: &Mechanism, run: &Run) -> Result<usize, ReplayError> {
    if let Some(name) = run.mechanism() {
        if name != mech.name {
            return Err(ReplayError::Input(format!(
                "the run is of mechanism `{name}`, the mechanism file is `{}`",
                mech.name
            )));
        }
    }
    Ok(mech.joint_count())
}

/// The input frames of `run` on `mech` and the host's `f32` monitor run.
/// The run must be of the mechanism (its `mechanism` metadata, when given)
/// and have 1 to 4 joints.
pub fn prepare(mech: &Mechanism, run: &Run) -> Result<Prepared, ReplayError> {
    let n = run_of(mech, run)?;
    with_joints!(n, N => prepare_n::<N>(mech, run), else Err(ReplayError::Input(format!(
        "{}: {n} joints; the monitor is built for 1 to 4",
        mech.name
    ))))
}

/// Splits frames, each with its `0x00`.
pub fn frames(bytes: &[u8]) -> impl Iterator<Item = &[u8]> {
    bytes.split_inclusive(|&b| b == 0)
}

fn decode_n<const N: usize>(bytes: &[u8]) -> Result<Vec<StatusRow>, ReplayError> {
    frames(bytes)
        .enumerate()
        .map(|(i, f)| {
            let mut f = f.to_vec();
            telemetry::decode::<Status<N>>(&mut f)
                .map(|s| StatusRow::from(&s))
                .map_err(|e| ReplayError::Target(format!("status frame {i}: {e}")))
        })
        .collect()
}

/// Decodes status frames of `joints` joints.
pub fn decode_statuses(bytes: &[u8], joints: usize) -> Result<Vec<StatusRow>, ReplayError> {
    with_joints!(joints, N => decode_n::<N>(bytes), else Err(ReplayError::Input(format!("{joints} joints"))))
}

/// Field name → value of a serialisable value, for the comparison.
fn fields<T: serde::Serialize>(value: &T) -> Vec<(String, serde_json::Value)> {
    match serde_json::to_value(value) {
        Ok(serde_json::Value::Object(m)) => m.into_iter().collect(),
        Ok(v) => vec![("value".into(), v)],
        Err(_) => Vec::new(),
    }
}

/// Compares the host's status frames with a target's, byte for byte; on a
/// difference, names the first differing frame, joint and field (decoded
/// with `joints`). Returns the number of frames when identical.
pub fn compare(host: &[u8], target: &[u8], joints: usize) -> Result<usize, Mismatch> {
    let (h, t): (Vec<&[u8]>, Vec<&[u8]>) = (frames(host).collect(), frames(target).collect());
    if host == target {
        return Ok(h.len());
    }
    let Some(i) = h.iter().zip(t.iter()).position(|(a, b)| a != b) else {
        return Err(Mismatch {
            frame: h.len().min(t.len()),
            joint: None,
            field: "number of frames".into(),
            host: h.len().to_string(),
            target: t.len().to_string(),
        });
    };
    let bytes = Mismatch {
        frame: i,
        joint: None,
        field: "frame bytes".into(),
        host: format!("{:02x?}", h[i]),
        target: format!("{:02x?}", t[i]),
    };
    let (Ok(a), Ok(b)) = (decode_statuses(h[i], joints), decode_statuses(t[i], joints)) else {
        return Err(bytes);
    };
    let (a, b) = (&a[0], &b[0]);
    let top = [
        ("t_s", bits(a.t_s), bits(b.t_s)),
        ("samples", a.samples.to_string(), b.samples.to_string()),
    ];
    for (field, x, y) in top {
        if x != y {
            return Err(Mismatch {
                frame: i,
                joint: None,
                field: field.into(),
                host: x,
                target: y,
            });
        }
    }
    for (j, (x, y)) in a.joints.iter().zip(b.joints.iter()).enumerate() {
        for ((name, u), (_, v)) in fields(x).into_iter().zip(fields(y)) {
            if u != v {
                return Err(Mismatch {
                    frame: i,
                    joint: Some(j + 1),
                    field: name,
                    host: u.to_string(),
                    target: v.to_string(),
                });
            }
        }
    }
    Err(bytes)
}

fn bits(x: f32) -> String {
    format!("{x:?} ({:#010x})", x.to_bits())
}

/// A value of the status CSV: `f32` in Rust's shortest form that reads back
/// to the same value, so equal statuses give equal text.
fn num(x: f32) -> String {
    if x.is_nan() {
        "NaN".into()
    } else {
        format!("{x}")
    }
}

/// The per-joint columns of the status CSV: name before the joint number,
/// name after it, and the value. The one place to change when the core's
/// `JointStatus` changes.
type Column = (&'static str, &'static str, fn(&JointStatus) -> String);

/// The per-joint columns, in order (documented in `docs/monitor.md` §1.1).
pub const JOINT_COLUMNS: [Column; 11] = [
    ("phi", "_deg", |s| num(s.phi_deg)),
    ("rate", "_deg_s", |s| num(s.rate_deg_s)),
    ("coulomb", "_nm", |s| num(s.coulomb_nm)),
    ("coulomb", "_sd_nm", |s| num(s.coulomb_sd_nm)),
    ("viscous", "_nms", |s| num(s.viscous_nms)),
    ("viscous", "_sd_nms", |s| num(s.viscous_sd_nms)),
    ("viscous", "_obs", |s| s.viscous.as_str().into()),
    ("latch", "", |s| s.latch.as_str().into()),
    ("margin", "_pct", |s| {
        s.margin_pct.map(num).unwrap_or_default()
    }),
    ("prediction", "", |s| s.prediction.as_str().into()),
    ("faults", "", |s| fault_names(s)),
];

fn fault_names(s: &JointStatus) -> String {
    s.faults
        .iter()
        .map(|f| f.as_str())
        .collect::<Vec<_>>()
        .join("|")
}

/// The header of the status CSV for `joints` joints.
pub fn status_header(joints: usize) -> Vec<String> {
    let mut h = vec!["t_s".to_string()];
    for j in 1..=joints {
        for (pre, post, _) in JOINT_COLUMNS {
            h.push(format!("{pre}{j}{post}"));
        }
    }
    h
}

/// Writes the status stream as CSV: [`status_header`], then one row per status.
pub fn write_status_csv<W: Write>(out: W, statuses: &[StatusRow]) -> io::Result<()> {
    let joints = statuses.first().map_or(0, |s| s.joints.len());
    let mut w = csv::Writer::from_writer(out);
    w.write_record(status_header(joints))?;
    for s in statuses {
        let mut row = vec![num(s.t_s)];
        for js in &s.joints {
            row.extend(JOINT_COLUMNS.iter().map(|(_, _, f)| f(js)));
        }
        w.write_record(row)?;
    }
    w.flush()
}

/// What a replay says about one joint.
#[derive(Clone, Debug, PartialEq)]
pub struct JointSummary {
    /// 1-based joint.
    pub joint: usize,
    /// First time the state is `latched` \[s\].
    pub latched_s: Option<f32>,
    /// Time from which the state stays `latched` to the end \[s\]: later
    /// than [`JointSummary::latched_s`] when the joint escaped its latch
    /// and latched again; `None` when it is not latched at the end.
    pub latched_final_s: Option<f32>,
    /// The state at the end.
    pub final_state: &'static str,
    /// Final Coulomb estimate and its standard deviation [N·m].
    pub coulomb_nm: (f32, f32),
    /// Final viscous estimate and its standard deviation [N·m·s/rad].
    pub viscous_nms: (f32, f32),
    /// Smallest torque margin of the run and the last one [%].
    pub margin_pct: (Option<f32>, Option<f32>),
    /// The last prediction.
    pub prediction: &'static str,
    /// Every fault flag raised during the run.
    pub faults: String,
}

// Its words: `onboard::summary_words`.

/// The per-joint summary of a status stream.
pub fn summary(statuses: &[StatusRow]) -> Vec<JointSummary> {
    let joints = statuses.first().map_or(0, |s| s.joints.len());
    (0..joints)
        .map(|j| {
            let (mut latched_s, mut latched_final_s) = (None, None);
            let mut min_margin: Option<f32> = None;
            let mut faults = deploywatch_core::FaultFlags::EMPTY;
            for s in statuses {
                let js = &s.joints[j];
                if js.latch == deploywatch_core::LatchState::Latched {
                    latched_s = latched_s.or(Some(s.t_s));
                    latched_final_s = latched_final_s.or(Some(s.t_s));
                } else {
                    latched_final_s = None;
                }
                if let Some(m) = js.margin_pct.filter(|m| m.is_finite()) {
                    min_margin = Some(min_margin.map_or(m, |x| x.min(m)));
                }
                faults = faults.union(js.faults);
            }
            let last = statuses.last().map(|s| s.joints[j]).unwrap_or_default();
            JointSummary {
                joint: j + 1,
                latched_s,
                latched_final_s,
                final_state: last.latch.as_str(),
                coulomb_nm: (last.coulomb_nm, last.coulomb_sd_nm),
                viscous_nms: (last.viscous_nms, last.viscous_sd_nms),
                margin_pct: (min_margin, last.margin_pct),
                prediction: last.prediction.as_str(),
                faults: faults
                    .iter()
                    .map(|f| f.as_str())
                    .collect::<Vec<_>>()
                    .join("|"),
            }
        })
        .collect()
}

/// Draws the status stream: joint angles, Coulomb estimates and the
/// energy margin of the remaining stroke, with the latch instants.
pub fn plot(png: &Path, title: &str, statuses: &[StatusRow]) -> Result<(), plot::PlotError> {
    let joints = statuses.first().map_or(0, |s| s.joints.len());
    let t: Vec<f64> = statuses.iter().map(|s| f64::from(s.t_s)).collect();
    let col = |f: fn(&JointStatus) -> f64| -> Vec<Vec<f64>> {
        (0..joints)
            .map(|j| statuses.iter().map(|s| f(&s.joints[j])).collect())
            .collect()
    };
    let phi = col(|s| f64::from(s.phi_deg));
    let coulomb = col(|s| f64::from(s.coulomb_nm));
    let margin = col(|s| s.margin_pct.map_or(f64::NAN, f64::from));
    let markers: Vec<(f64, String)> = summary(statuses)
        .iter()
        .flat_map(JointSummary::latch_marks)
        .collect();
    let upper = margin_axis_top_pct(&margin);
    plot::draw_with_axes(
        png,
        &format!("{title}: on-board monitor"),
        "time [s]",
        &[
            (
                panel(
                    "joint angle φ_j (filtered)",
                    "angle [deg]",
                    &t,
                    &phi,
                    &markers,
                ),
                plot::YAxis::default(),
            ),
            (
                panel(
                    "Coulomb friction estimate",
                    "T_C [N·m]",
                    &t,
                    &coulomb,
                    &markers,
                ),
                plot::YAxis::default(),
            ),
            (
                panel(
                    &format!(
                        "energy margin of the remaining stroke (axis clipped at {upper:.0} %; \
                         the monitor caps at {:.0} %)",
                        deploywatch_core::margin::MARGIN_CAP_PCT
                    ),
                    "margin [%]",
                    &t,
                    &margin,
                    &markers,
                ),
                plot::YAxis {
                    limits: Some((MARGIN_AXIS_BOTTOM_PCT, upper)),
                    lines: vec![(0.0, "0 % (no reserve)".into())],
                },
            ),
        ],
    )
}

/// The bottom of the margin axis [%]: the monitor's margin never goes
/// below −100 % (no driving energy left).
const MARGIN_AXIS_BOTTOM_PCT: f64 = -100.0;

/// The top of the margin axis [%]: 1.2 × the largest margin below the
/// monitor's cap, between 100 % and 1000 %, so that the cap (the joint
/// inside its capture zone, or no resistance yet) does not flatten the
/// margins that matter, near 0 %.
fn margin_axis_top_pct(margin: &[Vec<f64>]) -> f64 {
    let cap = f64::from(deploywatch_core::margin::MARGIN_CAP_PCT);
    let largest = margin
        .iter()
        .flatten()
        .copied()
        .filter(|m| m.is_finite() && *m < cap)
        .fold(0.0, f64::max);
    (1.2 * largest).clamp(100.0, 1000.0)
}

fn panel<'a>(
    title: &str,
    y_label: &str,
    t: &'a [f64],
    ys: &'a [Vec<f64>],
    markers: &[(f64, String)],
) -> Panel<'a> {
    Panel {
        title: title.into(),
        y_label: y_label.into(),
        series: ys
            .iter()
            .enumerate()
            .map(|(j, y)| Series {
                label: format!("joint {}", j + 1),
                x: t,
                y: y.as_slice(),
                mark: Mark::Line,
                color: j,
            })
            .collect(),
        markers: markers.to_vec(),
    }
}

/// A firmware ELF: `elf` when given, else `default` (a path relative to
/// the repository) under the current directory, else under the source tree
/// this program was built from; the error names the paths tried and `hint`.
pub(crate) fn find_firmware(
    elf: Option<&Path>,
    default: &str,
    hint: &str,
) -> Result<PathBuf, ReplayError> {
    let candidates: Vec<PathBuf> = match elf {
        Some(e) => vec![e.to_path_buf()],
        None => vec![
            PathBuf::from(default),
            Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("..")
                .join(default),
        ],
    };
    candidates
        .iter()
        .find(|p| p.is_file())
        .cloned()
        .ok_or_else(|| {
            ReplayError::Setup(format!(
                "no firmware ELF at {}: {hint}",
                candidates
                    .iter()
                    .map(|p| p.display().to_string())
                    .collect::<Vec<_>>()
                    .join(" or ")
            ))
        })
}

/// What a QEMU run of the firmware gave.
#[derive(Clone, Debug)]
pub struct QemuRun {
    /// The status frames the firmware wrote.
    pub frames: Vec<u8>,
    /// The firmware's defmt log, decoded when `defmt-print` is installed,
    /// else a note where the raw log is.
    pub log: String,
}

/// QEMU's `-semihosting-config` value that hands the firmware its input and
/// output files (each path without white space, at most 127 bytes, commas
/// doubled).
fn semihosting_args(in_path: &Path, out_path: &Path) -> Result<String, ReplayError> {
    let mut args = "enable=on,target=native,arg=deploywatch-firmware-example".to_string();
    for p in [&in_path, &out_path] {
        let s = p
            .to_str()
            .ok_or_else(|| ReplayError::Input(format!("{}: not UTF-8", p.display())))?;
        if s.chars().any(char::is_whitespace) || s.len() > 127 {
            return Err(ReplayError::Input(format!(
                "{s}: a semihosting argument may not contain spaces nor exceed 127 bytes \
                 (choose another --keep directory or TMPDIR)"
            )));
        }
        args.push_str(",arg=");
        args.push_str(&s.replace(',', ",,"));
    }
    Ok(args)
}

/// Waits for QEMU to exit, killing it after `timeout`.
fn wait_for(
    child: &mut std::process::Child,
    timeout: Duration,
) -> Result<std::process::ExitStatus, ReplayError> {
    let start = Instant::now();
    let status = loop {
        match child.try_wait() {
            Ok(Some(st)) => break st,
            Ok(None) if start.elapsed() > timeout => {
                let _ = child.kill();
                let _ = child.wait();
                return Err(ReplayError::Target(format!(
                    "the firmware did not finish within {} s (QEMU killed)",
                    timeout.as_secs()
                )));
            }
            Ok(None) => std::thread::sleep(Duration::from_millis(20)),
            Err(e) => return Err(ReplayError::Target(format!("waiting for {QEMU}: {e}"))),
        }
    };
    Ok(status)
}

/// Runs the firmware `elf` under QEMU on `input` (the files go to `dir`:
/// `input.bin`, `qemu.bin`, `qemu.defmt`), waiting at most `timeout`.
pub fn run_qemu(
    elf: &Path,
    input: &[u8],
    dir: &Path,
    timeout: Duration,
) -> Result<QemuRun, ReplayError> {
    let io_err = |p: &Path, e: io::Error| ReplayError::Input(format!("{}: {e}", p.display()));
    std::fs::create_dir_all(dir).map_err(|e| io_err(dir, e))?;
    let abs = |p: PathBuf| std::path::absolute(&p).unwrap_or(p);
    let in_path = abs(dir.join("input.bin"));
    let out_path = abs(dir.join("qemu.bin"));
    let log_path = dir.join("qemu.defmt");
    std::fs::write(&in_path, input).map_err(|e| io_err(&in_path, e))?;
    let _ = std::fs::remove_file(&out_path);
    let args = semihosting_args(&in_path, &out_path)?;
    let log = std::fs::File::create(&log_path).map_err(|e| io_err(&log_path, e))?;
    let mut child = Command::new(QEMU)
        .args(["-cpu", "cortex-m4", "-machine", "mps2-an386", "-nographic"])
        // One instruction per ns of virtual time: the firmware's instruction
        // count of Monitor::update relies on it.
        .args([
            "-icount",
            "shift=0",
            "-semihosting-config",
            &args,
            "-kernel",
        ])
        .arg(elf)
        .stdin(Stdio::null())
        .stdout(log)
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| match e.kind() {
            io::ErrorKind::NotFound => {
                ReplayError::Setup(format!("{QEMU} is not installed: {SETUP_HINT}"))
            }
            _ => ReplayError::Setup(format!("cannot start {QEMU}: {e}")),
        })?;
    let status = wait_for(&mut child, timeout)?;
    let mut stderr = String::new();
    if let Some(mut e) = child.stderr.take() {
        let _ = io::Read::read_to_string(&mut e, &mut stderr);
    }
    let log = decode_log(elf, &log_path);
    match status.code() {
        Some(0) => {}
        code => {
            let what = match code {
                Some(1) => "the firmware reported an error".to_string(),
                Some(101) => "the firmware panicked".to_string(),
                Some(134) => "the firmware hit a hard fault".to_string(),
                Some(c) => format!("QEMU exited with {c}"),
                None => "QEMU was killed by a signal".to_string(),
            };
            return Err(ReplayError::Target(format!("{what}\n{log}{stderr}")));
        }
    }
    let frames = std::fs::read(&out_path).map_err(|e| io_err(&out_path, e))?;
    Ok(QemuRun { frames, log })
}

/// The firmware's log: `defmt-print -e ELF < LOG` when it is installed.
fn decode_log(elf: &Path, log_path: &Path) -> String {
    let decoded = std::fs::File::open(log_path).ok().and_then(|f| {
        Command::new("defmt-print")
            .arg("-e")
            .arg(elf)
            .stdin(f)
            .stderr(Stdio::null())
            .output()
            .ok()
    });
    match decoded {
        Some(o) => String::from_utf8_lossy(&o.stdout).into_owned(),
        None => format!(
            "(defmt-print not installed: raw log in {}; decode with defmt-print -e {})\n",
            log_path.display(),
            elf.display()
        ),
    }
}
