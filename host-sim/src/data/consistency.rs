//! Whether a run means what its mechanism says, checked before any work:
//! the units of its angles and times, the sign of its encoders, its latch
//! switches. The format reader ([`crate::data::run`]) checks syntax; this
//! checks meaning, with the likely cause named.
//!
//! Every command that pairs a run with a mechanism (`identify`, `diagnose`
//! through [`crate::data::campaign::Campaign::push`], `replay`) calls
//! [`check`] before it simulates anything. A finding that makes the run
//! unusable is an error ([`RunErrorKind::AnglesInRadians`],
//! [`RunErrorKind::MirroredEncoder`], [`RunErrorKind::SwappedColumns`], [`RunErrorKind::AnglesWholeTurnsOff`],
//! [`RunErrorKind::AnglesWrap`],
//! [`RunErrorKind::AnglesFromStowed`], [`RunErrorKind::TimeInMilliseconds`]);
//! one where the data may be right is a warning, returned as a line of text.

use crate::data::run::{Run, RunError, RunErrorKind, MIN_MOTION_DEG};
use crate::model::mechanism::Mechanism;

/// Degrees per radian: an angle read in radians is this many times smaller
/// than the same angle in degrees (57.3).
const DEG_PER_RAD: f64 = 180.0 / std::f64::consts::PI;

/// Smallest stowed angle whose reading tells degrees from radians, and a
/// sign flip from the stowed pose \[deg\]: ten times [`MIN_MOTION_DEG`], so
/// the hypotheses (φ₀, φ₀/57.3, −φ₀) are at least 9.8 deg apart, far beyond
/// encoder noise (0.02 deg) and a typical encoder offset.
const MIN_STOWED_FOR_UNITS_DEG: f64 = 10.0 * MIN_MOTION_DEG;

/// How far from a whole turn a jump between two readings may be and still
/// be an encoder's wrap \[deg\]: a quarter turn (no hinge turns 270 deg
/// between two samples of a deployment).
const WRAP_SLACK_DEG: f64 = 90.0;

/// Largest reading of a joint recorded in radians [rad as written]: the
/// reader's bound, ±720 deg, in radians (4π). A joint recorded in degrees
/// that deploys from a stowed angle of 10 deg or more spans more than that.
const MAX_RADIAN_READING: f64 = 4.0 * std::f64::consts::PI;

/// Largest distance of a joint's reading at the start from its stowed angle
/// that needs no word \[deg\]: ten times [`MIN_MOTION_DEG`], beyond encoder
/// noise (0.02 deg) and the encoder offsets a mounting leaves (a few
/// tenths of a degree).
const START_OFFSET_WARN_DEG: f64 = 10.0 * MIN_MOTION_DEG;

/// Readings whose median is a joint's reading at the start: five, so that
/// two corrupted ones among them (a spike, parity errors) do not decide.
const START_SAMPLES: usize = 5;

/// The readings of a joint's start lie within this of its first reading
/// \[s\]: five samples at 100 Hz, the first alone at 2 Hz, where five
/// would span the deployment.
const START_WINDOW_S: f64 = 0.05;

/// How many times the mechanism's `duration_s` a run may last before its
/// times are taken for milliseconds: a recording a hundred simulation
/// horizons long is no one deployment, and milliseconds make it a thousand.
const MAX_DURATION_FACTOR: f64 = 100.0;

/// How many times the mechanism's sample interval (`1 / sample_hz`) a run's
/// median interval may be, in a run that outlasts `duration_s`, before its
/// times are taken for milliseconds: a rig sampling at 100 Hz to 1 kHz
/// writes intervals of 10 to 1 "s" in milliseconds, 1000 to 100 times a
/// 100 Hz mechanism's 0.01 s; a run in seconds sampled ten times slower
/// than its mechanism is too coarse to diagnose anyway.
const MS_RATE_FACTOR: f64 = 10.0;

/// Fewest samples over the mechanism's `duration_s` that show a
/// deployment's shape; coarser sampling is a warning.
const MIN_SAMPLES_PER_HORIZON: f64 = 10.0;

/// Checks `run` (read from `file`) against `mechanism` before any
/// simulation. Returns the warnings (`file:line: ...`, without the
/// `warning:` prefix), or the first error:
/// - two joints' first samples are each the other's stowed angle:
///   [`RunErrorKind::SwappedColumns`] (at ±180 deg, where that is also
///   each one's own pose a turn off, [`RunErrorKind::SwappedOrMirrored`]
///   once both have moved towards 0 on the side they started, and named
///   in their warnings before that);
/// - the first sample is the stowed angle in radians (ratio 57.3):
///   [`RunErrorKind::AnglesInRadians`];
/// - the first sample is minus the stowed angle (a mirrored encoder) on a
///   joint whose stowed angle is not ±180 deg: [`RunErrorKind::MirroredEncoder`]
///   (at ±180 deg, −φ₀ is the same pose one turn on: a warning);
/// - the first sample is whole turns from the stowed angle:
///   [`RunErrorKind::AnglesWholeTurnsOff`]; a reading that jumps by about
///   a turn between two samples: [`RunErrorKind::AnglesWrap`]; near 0 with
///   the readings moving
///   away from 0: [`RunErrorKind::AnglesFromStowed`]; otherwise more than
///   [`START_OFFSET_WARN_DEG`] from the stowed angle: a warning;
/// - the run lasts more than [`MAX_DURATION_FACTOR`] × `duration_s`:
///   [`RunErrorKind::TimeInMilliseconds`]; or it lasts more than
///   `duration_s` with samples more than
///   [`MS_RATE_FACTOR`] times the mechanism's sample interval apart:
///   [`RunErrorKind::TimeInMillisecondsBySampleRate`] (a long `duration_s`);
/// - warnings: fewer than [`MIN_SAMPLES_PER_HORIZON`] samples over
///   `duration_s`; a latch switch closed at the first sample of a joint
///   that then moves (a stuck switch or an inverted column), or never
///   closed on a joint that reaches its latch angle (a switch stuck open);
///   a gap between samples longer than a tenth of `duration_s`; an ideal
///   latch that let go ([`let_go`]); a reading that glitches
///   ([`crate::data::glitch`]).
///
/// A latch that never closes is no finding: that is a failed deployment,
/// which is what the analyses are for.
pub fn check(run: &Run, mechanism: &Mechanism, file: &str) -> Result<Vec<String>, RunError> {
    let mut warnings = Vec::new();
    if run.is_empty() {
        return Ok(warnings);
    }
    check_time(run, mechanism, file, &mut warnings)?;
    // Swapped or mirrored at ±180 deg is told after the joints' own
    // findings: where every encoder is mirrored, the joint that says so
    // alone is named.
    let (swap, deferred) = match check_swap(run, mechanism, file) {
        Ok(pair) => (pair, None),
        Err(e) => match e.kind {
            RunErrorKind::SwappedOrMirrored { joints: [a, b], .. } => {
                (Some((a - 1, b - 1)), Some(e))
            }
            _ => return Err(e),
        },
    };
    for (j, joint) in mechanism.joints.iter().enumerate().take(run.joints()) {
        let other = swap.and_then(|(a, b)| [(a, b), (b, a)].into_iter().find(|p| p.0 == j));
        let swap = other.map(|(_, k)| k);
        check_angles(run, j, joint.stowed_deg, swap, file, &mut warnings)?;
    }
    if let Some(e) = deferred {
        return Err(e);
    }
    check_latches(run, file, &mut warnings);
    warnings.extend(crate::data::glitch::warnings(run, file, |i| {
        line_of_sample(run, i)
    }));
    for j in
        (0..run.joints().min(mechanism.joint_count())).filter(|&j| mechanism.latch(j).is_none())
    {
        if let Some(g) = let_go(run, j) {
            warnings.push(format!(
                "{file}:{line}: column `latch{joint}` (column {column}): joint {joint}'s switch \
                 opens again at t = {opened} s after closing at t = {closed} s, and the reading \
                 leaves the stop by up to {left:.2} deg: a latch that let go; the mechanism's \
                 latch is ideal and holds, so no effect explains the run after {opened} s (cut \
                 the run there to fit the motion before it)",
                line = line_of_sample(run, g.opened),
                joint = j + 1,
                column = 2 + run.joints() + j,
                opened = run.t_s[g.opened],
                closed = run.t_s[g.closed],
                left = g.left_deg,
            ));
        }
    }
    Ok(warnings)
}

/// Fewest consecutive samples a latch switch reads open again after
/// closing for its latch to have let go: fewer is a switch's chatter.
pub const LET_GO_SAMPLES: usize = 3;

/// A latch that let go in a run ([`let_go`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LetGo {
    /// The sample where the switch first closed.
    pub closed: usize,
    /// The first sample of the switch's opening again.
    pub opened: usize,
    /// How far the reading leaves its closing reading after that \[deg\].
    pub left_deg: f64,
}

/// Joint `j`'s latch letting go in `run`: its switch reads open again for
/// [`LET_GO_SAMPLES`] samples or more (or to the end of the run) after it
/// first closed, and the reading leaves its reading at the closing by
/// [`MIN_MOTION_DEG`] or more after that. `None` for a switch that stays
/// closed, chatters, or opens with the panel still on its stop.
pub fn let_go(run: &Run, j: usize) -> Option<LetGo> {
    let latch = run.latch.get(j)?;
    let phi = run.phi_deg.get(j)?;
    let closed = latch.iter().position(|&l| l)?;
    let mut k = closed;
    while k < latch.len() {
        if latch[k] {
            k += 1;
            continue;
        }
        let open = latch[k..].iter().take_while(|&&l| !l).count();
        if open >= LET_GO_SAMPLES || k + open == latch.len() {
            let left_deg = phi[k..]
                .iter()
                .filter(|x| x.is_finite())
                .map(|x| (x - phi[closed]).abs())
                .fold(0.0, f64::max);
            if left_deg >= MIN_MOTION_DEG {
                return Some(LetGo {
                    closed,
                    opened: k,
                    left_deg,
                });
            }
        }
        k += open;
    }
    None
}

/// Line number of sample `i` in the file: the metadata lines, the header,
/// then one row per sample (`docs/spec/formats.md`).
pub(crate) fn line_of_sample(run: &Run, i: usize) -> usize {
    run.metadata.len() + 2 + i
}

/// The first sample of a series (its index) and its reading at the start:
/// the median of its first [`START_SAMPLES`] finite readings within
/// [`START_WINDOW_S`] of it (`t` the run's times), so that one corrupted
/// reading (a spike, a parity error) does not decide.
fn start_reading(series: &[f64], t: &[f64]) -> Option<(usize, f64)> {
    let i0 = series.iter().position(|x| x.is_finite())?;
    let t0 = t.get(i0).copied().unwrap_or(0.0);
    let mut first: Vec<f64> = series[i0..]
        .iter()
        .zip(t.get(i0..).unwrap_or_default())
        .filter(|(x, &ti)| x.is_finite() && ti - t0 <= START_WINDOW_S)
        .map(|(&x, _)| x)
        .take(START_SAMPLES)
        .collect();
    if first.is_empty() {
        first.push(series[i0]);
    }
    first.sort_by(f64::total_cmp);
    Some((i0, first[first.len() / 2]))
}

/// The median interval between samples [s as written].
fn median_interval(t: &[f64]) -> f64 {
    let mut d: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
    if d.is_empty() {
        return 0.0;
    }
    d.sort_by(f64::total_cmp);
    d[d.len() / 2]
}

fn check_time(
    run: &Run,
    mechanism: &Mechanism,
    file: &str,
    warnings: &mut Vec<String>,
) -> Result<(), RunError> {
    let (first, last) = (run.t_s[0], run.t_s[run.len() - 1]);
    let span_s = last - first;
    let horizon_s = mechanism.duration_s;
    let interval_s = median_interval(&run.t_s);
    if span_s > MAX_DURATION_FACTOR * horizon_s {
        return Err(RunError::at(
            file,
            line_of_sample(run, run.len() - 1),
            RunErrorKind::TimeInMilliseconds {
                span_s,
                interval_s,
                factor: span_s / horizon_s,
                mechanism: mechanism.name.clone(),
                duration_s: horizon_s,
            },
        ));
    }
    let rate_factor = interval_s * mechanism.sample_hz;
    if span_s > horizon_s && rate_factor > MS_RATE_FACTOR {
        return Err(RunError::at(
            file,
            line_of_sample(run, 1),
            RunErrorKind::TimeInMillisecondsBySampleRate {
                span_s,
                interval_s,
                rate_factor,
                mechanism: mechanism.name.clone(),
                sample_hz: mechanism.sample_hz,
                duration_s: horizon_s,
            },
        ));
    }
    let gap_allowed_s = horizon_s / MIN_SAMPLES_PER_HORIZON;
    if interval_s > gap_allowed_s {
        warnings.push(format!(
            "{file}:{}: column `t_s` (column 1): samples {interval_s} s apart, fewer than {MIN_SAMPLES_PER_HORIZON} over mechanism \"{}\"'s duration_s = {horizon_s} s: too coarse to show a deployment; is the sample rate right?",
            line_of_sample(run, 1),
            mechanism.name
        ));
    } else if let Some((i, gap)) = run
        .t_s
        .windows(2)
        .map(|w| w[1] - w[0])
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .filter(|&(_, gap)| gap > gap_allowed_s)
    {
        warnings.push(format!(
            "{file}:{}: column `t_s` (column 1): no sample for {gap:.4} s, from t = {} s to t = {} s, more than a tenth of mechanism \"{}\"'s duration_s = {horizon_s} s: samples lost? the analyses use the samples there are, and what happened in the gap is not seen",
            line_of_sample(run, i + 1),
            run.t_s[i],
            run.t_s[i + 1],
            mechanism.name
        ));
    }
    Ok(())
}

/// Distance between two angles up to whole turns \[deg\]: 0 for the same
/// pose, at most 180.
fn off_by_turns(a: f64, b: f64) -> f64 {
    let d = a - b;
    (d - 360.0 * (d / 360.0).round()).abs()
}

/// Two joints of `run` (0-based) whose readings at the start are each
/// within [`START_OFFSET_WARN_DEG`] of the other's stowed angle and not of
/// their own, where their stowed angles differ: their columns swapped.
/// Refused ([`RunErrorKind::SwappedColumns`]) unless each reading is also
/// its own joint's pose a turn off (stowed at ±180 deg, where −180 and 180
/// are one pose); that pair is returned, for the warnings of the joints.
fn check_swap(
    run: &Run,
    mechanism: &Mechanism,
    file: &str,
) -> Result<Option<(usize, usize)>, RunError> {
    let n = run.joints().min(mechanism.joint_count());
    let stowed = |j: usize| mechanism.joints[j].stowed_deg;
    let starts: Vec<Option<(usize, f64)>> = (0..n)
        .map(|j| start_reading(&run.phi_deg[j], &run.t_s))
        .collect();
    let near = |x: f64, target: f64| (x - target).abs() <= START_OFFSET_WARN_DEG;
    for a in 0..n {
        for b in a + 1..n {
            let (Some((i0, from_a)), Some((_, from_b))) = (starts[a], starts[b]) else {
                continue;
            };
            let swapped = !near(stowed(a), stowed(b))
                && near(from_a, stowed(b))
                && near(from_b, stowed(a))
                && !near(from_a, stowed(a))
                && !near(from_b, stowed(b));
            if !swapped {
                continue;
            }
            let own_pose = off_by_turns(from_a, stowed(a)) <= START_OFFSET_WARN_DEG
                && off_by_turns(from_b, stowed(b)) <= START_OFFSET_WARN_DEG;
            let joints = [a + 1, b + 1];
            let (found, stowed_deg) = ([from_a, from_b], [stowed(a), stowed(b)]);
            let kind = if !own_pose {
                RunErrorKind::SwappedColumns {
                    joints,
                    found,
                    stowed_deg,
                }
            } else if moved_mirrored(&run.phi_deg[a], from_a, stowed(a))
                && moved_mirrored(&run.phi_deg[b], from_b, stowed(b))
            {
                RunErrorKind::SwappedOrMirrored {
                    joints,
                    found,
                    stowed_deg,
                }
            } else {
                return Ok(Some((a, b)));
            };
            return Err(RunError::at(file, line_of_sample(run, i0), kind));
        }
    }
    Ok(None)
}

/// A jump of about a turn between two readings of joint `j`: a wrap,
/// whatever the rate (no hinge turns 270 deg between two samples of a
/// deployment).
fn check_wrap(run: &Run, j: usize, file: &str) -> Result<(), RunError> {
    let finite: Vec<(usize, f64)> = run.phi_deg[j]
        .iter()
        .copied()
        .enumerate()
        .filter(|(_, x)| x.is_finite())
        .collect();
    match finite
        .windows(2)
        .find(|w| ((w[1].1 - w[0].1).abs() - 360.0).abs() < WRAP_SLACK_DEG)
    {
        Some(w) => Err(RunError::at(
            file,
            line_of_sample(run, w[1].0),
            RunErrorKind::AnglesWrap {
                joint: j + 1,
                from: w[0].1,
                to: w[1].1,
            },
        )),
        None => Ok(()),
    }
}

/// The first sample of joint `j` against its stowed angle; `swap`: the
/// joint (0-based) whose column this one's may be swapped with, each
/// reading the other's stowed angle and its own a turn off
/// ([`check_swap`]).
fn check_angles(
    run: &Run,
    j: usize,
    stowed_deg: f64,
    swap: Option<usize>,
    file: &str,
    warnings: &mut Vec<String>,
) -> Result<(), RunError> {
    let series = &run.phi_deg[j];
    let Some((i0, first)) = start_reading(series, &run.t_s) else {
        return Ok(());
    };
    check_wrap(run, j, file)?;
    // A joint that never moves (a stuck encoder, a failed release) says
    // nothing about units.
    let (lo, hi) = series
        .iter()
        .filter(|x| x.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &x| {
            (l.min(x), h.max(x))
        });
    if stowed_deg.abs() < MIN_STOWED_FOR_UNITS_DEG || hi - lo < MIN_MOTION_DEG {
        return Ok(());
    }
    let line = line_of_sample(run, i0);
    let degrees = (first - stowed_deg).abs();
    let radians = (first - stowed_deg / DEG_PER_RAD).abs();
    let mirrored = (first + stowed_deg).abs();
    let largest = series
        .iter()
        .filter(|x| x.is_finite())
        .fold(0.0_f64, |m, x| m.max(x.abs()));
    if radians < degrees && radians < mirrored && largest <= MAX_RADIAN_READING {
        return Err(RunError::at(
            file,
            line,
            RunErrorKind::AnglesInRadians {
                joint: j + 1,
                found: first,
                stowed_deg,
            },
        ));
    }
    // A start whole turns from the stowed angle is told in
    // `check_start_offset`; at ±180 deg it is the mirrored start itself.
    let turns = ((first - stowed_deg) / 360.0).round();
    let whole_turns = if turns == 0.0 {
        f64::INFINITY
    } else {
        (first - stowed_deg - 360.0 * turns).abs()
    };
    if mirrored < degrees && mirrored < radians && mirrored <= whole_turns {
        // At ±180 deg a start at minus the stowed angle is the stowed pose
        // as an encoder wrapping there reads it, until the joint moves: a
        // wrapping encoder's readings then jump by a turn (`check_wrap`),
        // a mirrored one's move towards 0 on the side they started.
        let at_half_turn = (stowed_deg.abs() - 180.0).abs() < MIN_STOWED_FOR_UNITS_DEG;
        if at_half_turn && (swap.is_some() || !moved_mirrored(series, first, stowed_deg)) {
            warnings.push(format!(
                "{file}:{line}: column `phi{joint}_deg` (column {column}): the run starts at {first} deg where joint {joint} is stowed at {stowed_deg} deg: {}?",
                mirrored_causes(j, swap),
                joint = j + 1,
                column = j + 2
            ));
        } else {
            return Err(RunError::at(
                file,
                line,
                RunErrorKind::MirroredEncoder {
                    joint: j + 1,
                    found: first,
                    stowed_deg,
                },
            ));
        }
        return Ok(());
    }
    check_start_offset(series, j, first, stowed_deg, file, line, warnings)
}

/// True when a joint stowed at `stowed_deg` whose readings `series` start
/// at `first` (minus its stowed angle) has moved [`START_OFFSET_WARN_DEG`]
/// or more towards 0 on the side it started: what a mirrored encoder
/// reads, where one wrapping at ±180 deg jumps by a turn
/// ([`check_wrap`]).
fn moved_mirrored(series: &[f64], first: f64, stowed_deg: f64) -> bool {
    series.iter().any(|&x| {
        x.is_finite()
            && x.signum() == first.signum()
            && stowed_deg.abs() - x.abs() >= START_OFFSET_WARN_DEG
    })
}

/// What makes joint `j` stowed at ±180 deg start at minus its stowed
/// angle, in words: a mirrored or wrapping encoder, or its column swapped
/// with joint `swap`'s ([`check_swap`]).
fn mirrored_causes(j: usize, swap: Option<usize>) -> String {
    match swap {
        None => "an encoder mounted mirrored, or one that wraps at ±180 deg".to_string(),
        Some(k) => format!(
            "an encoder mounted mirrored, one that wraps at ±180 deg, or the columns `phi{}_deg` and `phi{}_deg` swapped (each starts at the other joint's stowed angle)",
            j.min(k) + 1,
            j.max(k) + 1
        ),
    }
}

/// The reading at the start of joint `j` against its stowed angle, once
/// radians and a mirrored encoder are ruled out: a start at 0 deg that
/// moves away from 0 by about the stowed angle is an encoder counted from
/// the stowed pose; a start whole turns from the stowed angle is an encoder
/// counting 0 to 360 deg (errors); any other start further than
/// [`START_OFFSET_WARN_DEG`] from the stowed angle is a warning (a test
/// from another pose, or a large encoder offset: the data may be right, but
/// every simulation starts at `stowed_deg`).
fn check_start_offset(
    series: &[f64],
    j: usize,
    first: f64,
    stowed_deg: f64,
    file: &str,
    line: usize,
    warnings: &mut Vec<String>,
) -> Result<(), RunError> {
    let offset = first - stowed_deg;
    if offset.abs() <= START_OFFSET_WARN_DEG {
        return Ok(());
    }
    let turns = (offset / 360.0).round();
    if turns != 0.0 && (offset - 360.0 * turns).abs() <= START_OFFSET_WARN_DEG {
        return Err(RunError::at(
            file,
            line,
            RunErrorKind::AnglesWholeTurnsOff {
                joint: j + 1,
                found: first,
                stowed_deg,
                turns,
            },
        ));
    }
    // Counted from the stowed pose: the readings start near 0 and the
    // farthest lies on the side of -stowed_deg, at least half a stroke out.
    let farthest = series
        .iter()
        .filter(|x| x.is_finite())
        .fold(0.0_f64, |m, &x| if x.abs() > m.abs() { x } else { m });
    if first.abs() < offset.abs() / 2.0
        && farthest * -stowed_deg > 0.0
        && farthest.abs() >= stowed_deg.abs() / 2.0
    {
        return Err(RunError::at(
            file,
            line,
            RunErrorKind::AnglesFromStowed {
                joint: j + 1,
                found: first,
                stowed_deg,
            },
        ));
    }
    warnings.push(format!(
        "{file}:{line}: column `phi{joint}_deg` (column {column}): the run starts at {first} deg, {offset:.1} deg from joint {joint}'s stowed angle {stowed_deg} deg, where every simulation starts: a test from another pose, or an encoder offset? (the mechanism's `stowed_deg`)",
        joint = j + 1,
        column = j + 2
    ));
    Ok(())
}

/// Latch switches closed at the first sample of a joint that then moves,
/// or never closed on a joint that reaches its latch angle (0 deg, within
/// [`MIN_MOTION_DEG`]).
fn check_latches(run: &Run, file: &str, warnings: &mut Vec<String>) {
    let n = run.joints();
    for (j, latch) in run.latch.iter().enumerate() {
        let phi = &run.phi_deg[j];
        let Some(&first) = phi.iter().find(|x| x.is_finite()) else {
            continue;
        };
        let moves = phi
            .iter()
            .any(|x| x.is_finite() && (x - first).abs() >= MIN_MOTION_DEG);
        let reaches_latch = phi.iter().any(|x| x.abs() < MIN_MOTION_DEG);
        if moves && reaches_latch && !latch.iter().any(|&l| l) {
            let i = phi
                .iter()
                .position(|x| x.abs() < MIN_MOTION_DEG)
                .unwrap_or(0);
            let closest = phi
                .iter()
                .filter(|x| x.is_finite())
                .fold(f64::INFINITY, |a, x| a.min(x.abs()));
            warnings.push(format!(
                "{file}:{line}: column `latch{joint}` (column {column}): joint {joint} comes within {MIN_MOTION_DEG} deg of its latch angle (0 deg; {closest:.2} deg at the closest) but its switch never reads closed: a switch unwired or stuck open, or a joint stopped just short of its latch?",
                line = line_of_sample(run, i),
                joint = j + 1,
                column = 2 + n + j
            ));
        }
        if latch.first() == Some(&true) && moves {
            warnings.push(format!(
                "{file}:{line}: column `latch{joint}` (column {column}): joint {joint}'s latch reads closed at the first sample, before the joint moves: a switch stuck closed, or a column written inverted (1 = open)?",
                line = line_of_sample(run, 0),
                joint = j + 1,
                column = 2 + n + j
            ));
        }
    }
}

#[cfg(test)]
mod tests;
