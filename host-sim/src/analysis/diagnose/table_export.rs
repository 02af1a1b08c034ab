//! A host torque table as the on-board monitor can hold it: compressed to
//! the monitor's [`TABLE_MAX_KNOTS`] points per table, with the fit loss.
//!
//! The host's tables may have up to
//! [`crate::model::torque_table::HOST_TABLE_MAX_KNOTS`] points; the
//! monitor's chain holds [`TABLE_MAX_KNOTS`]. A table with more points on an
//! axis is compressed by least squares on the torques: the extended model
//! is simulated on every run of the campaign, the host table's torque
//! at each sample while the joint is free (the stroke and the rates the
//! data cover, weighted by the time spent there), each axis with more
//! points (`f(φ)` or `g(φ̇)`) is evaluated there and an 8-point table is
//! fitted to it by least squares on the torques
//! ([`crate::analysis::diagnose::residual_shape::fit_shape_with`] with
//! [`KnotScore::Rss`]: greedy knot insertion, each step adding the knot
//! that lowers the squared torque error most, `g(0) = 0` kept); an axis
//! that fits is kept as it is. The loss is
//! reported three ways: the RMS and the largest torque difference over
//! those samples [N·m], and the RMS difference of the angles \[deg\] between
//! the model with the host table and with the compressed one, re-simulated
//! on the campaign's runs. A table that fits already is exported as it is,
//! with no loss.

use crate::analysis::campaign_sim::CampaignSim;
use crate::analysis::diagnose::residual_shape::{fit_shape_with, Axis, KnotScore};
use crate::analysis::diagnose::residual_torque::TorqueSample;
use crate::data::campaign::Campaign;
use crate::model::effect::{encoder_offsets_deg, Effect, EffectKind, Law};
use crate::model::torque_table::{HostTable, HostTorqueTable};
use crate::simulate::deployment::Trajectory;
use deploywatch_core::physics::TABLE_MAX_KNOTS;
use deploywatch_core::{Table, TorqueTable};

/// A table for the monitor and what the compression cost.
#[derive(Clone, Debug, PartialEq)]
pub struct TableExport {
    /// 1-based joint of the table.
    pub joint: usize,
    /// The monitor's table: at most [`TABLE_MAX_KNOTS`] points per axis.
    pub table: TorqueTable<f64>,
    /// True when the host table had more points than the monitor holds.
    pub compressed: bool,
    /// RMS of host minus exported torque over the free samples [N·m].
    pub torque_rms_nm: f64,
    /// Largest absolute difference of the two torques there [N·m].
    pub torque_max_nm: f64,
    /// RMS difference of the re-simulated angles over all runs and joints
    /// \[deg\]; `None` when a simulation failed.
    pub angle_rms_deg: Option<f64>,
    /// Samples the torque difference is taken over.
    pub samples: usize,
}

/// The monitor's export of every `torque_table` among `effects` (the
/// diagnosis's extended model) on the runs of `campaign`.
pub fn export_tables(campaign: &Campaign, effects: &[Effect]) -> Vec<TableExport> {
    let tables: Vec<(usize, usize)> = effects
        .iter()
        .enumerate()
        .filter(|(_, e)| e.kind() == EffectKind::TorqueTable)
        .filter_map(|(k, e)| Some((k, e.joint?)))
        .collect();
    if tables.is_empty() {
        return Vec::new();
    }
    let trajectories: Vec<_> = (0..campaign.runs.len())
        .map(|i| campaign.simulate(i, effects).ok())
        .collect();
    tables
        .into_iter()
        .filter_map(|(k, joint)| {
            let host = effects[k].table()?;
            let j = joint.checked_sub(1)?;
            let samples = stroke_samples(campaign, &trajectories, effects, j, host);
            let (table, compressed) = compress(host, &samples, motion_of(campaign, j))?;
            let (torque_rms_nm, torque_max_nm) = torque_loss(host, &table, &samples);
            let angle_rms_deg = if compressed {
                angle_loss(campaign, &trajectories, effects, k, &table)
            } else {
                Some(0.0)
            };
            Some(TableExport {
                joint,
                table,
                compressed,
                torque_rms_nm,
                torque_max_nm,
                angle_rms_deg,
                samples: samples.len(),
            })
        })
        .collect()
}

/// The sign of `φ̇` while 0-based joint `j` deploys (towards the latch at 0).
fn motion_of(campaign: &Campaign, j: usize) -> f64 {
    campaign
        .runs
        .iter()
        .find_map(|r| r.mechanism.joints.get(j))
        .map_or(-1.0, |js| -js.stowed_deg.signum())
}

/// The samples of 0-based joint `j` while it is free, on the model's own
/// trajectories (true angles: the encoder offsets among `effects` taken
/// off), with the host table's torque as the value to fit (unit weights;
/// every run counted as one so that knots may go anywhere a run reaches).
fn stroke_samples(
    campaign: &Campaign,
    trajectories: &[Option<Trajectory>],
    effects: &[Effect],
    j: usize,
    table: &HostTorqueTable,
) -> Vec<TorqueSample> {
    let mut out = Vec::new();
    for (r, traj) in trajectories.iter().enumerate() {
        let (Some(traj), Some(run)) = (traj, campaign.runs.get(r)) else {
            continue;
        };
        let offsets = encoder_offsets_deg(effects, run.mechanism.joint_count());
        let b = offsets.get(j).copied().unwrap_or(0.0);
        let (Some(phi), Some(rate), Some(latched)) = (
            traj.phi_deg.get(j),
            traj.rate_deg_s.get(j),
            traj.latched.get(j),
        ) else {
            continue;
        };
        for (i, ((&p, &v), &l)) in phi.iter().zip(rate).zip(latched).enumerate() {
            let p = p - b;
            if l || !p.is_finite() || !v.is_finite() {
                continue;
            }
            out.push(TorqueSample {
                run: 0,
                index: i,
                t_s: traj.t_s.get(i).copied().unwrap_or(0.0),
                phi_deg: p,
                rate_deg_s: v,
                torque_nm: table.torque(p.to_radians(), v.to_radians()),
                se_nm: 1.0,
                spring_nm: 0.0,
                from_stowed_rad: 0.0,
                window: 1,
            });
        }
    }
    out
}

/// The monitor's table of `host`: each axis with at most
/// [`TABLE_MAX_KNOTS`] points as it is, each larger one replaced by the
/// least-squares fit of its own part (`f(φ)` or `g(φ̇)`) at the samples'
/// angles or rates with that many knots. The flag says whether any axis
/// was compressed.
fn compress(
    host: &HostTorqueTable,
    samples: &[TorqueSample],
    motion: f64,
) -> Option<(TorqueTable<f64>, bool)> {
    let mut compressed = false;
    let mut one = |t: &Option<HostTable>, axis: Axis| -> Option<Option<Table<f64>>> {
        let Some(t) = t else { return Some(None) };
        if t.xs().len() <= TABLE_MAX_KNOTS {
            return Some(Table::new(t.xs(), t.ys()).ok());
        }
        compressed = true;
        let part: Vec<TorqueSample> = samples
            .iter()
            .map(|s| TorqueSample {
                torque_nm: t.eval(match axis {
                    Axis::Angle => s.phi_deg,
                    Axis::Rate => s.rate_deg_s,
                }),
                ..*s
            })
            .collect();
        let shape = fit_shape_with(&part, motion, &[axis], TABLE_MAX_KNOTS, KnotScore::Rss)?;
        Some(match axis {
            Axis::Angle => Table::new(&shape.angle_deg, &shape.angle_nm).ok(),
            Axis::Rate => Table::new(&shape.rate_deg_s, &shape.rate_nm).ok(),
        })
    };
    let angle = one(&host.angle, Axis::Angle)?;
    let rate = one(&host.rate, Axis::Rate)?;
    Some((TorqueTable { angle, rate }, compressed))
}

/// RMS and largest absolute difference of the two tables' torques at the
/// samples [N·m].
fn torque_loss(
    host: &HostTorqueTable,
    export: &TorqueTable<f64>,
    s: &[TorqueSample],
) -> (f64, f64) {
    let d: Vec<f64> = s
        .iter()
        .map(|x| {
            let (p, v) = (x.phi_deg.to_radians(), x.rate_deg_s.to_radians());
            host.torque(p, v) - export.torque(p, v)
        })
        .collect();
    let n = d.len().max(1) as f64;
    let rms = (d.iter().map(|x| x * x).sum::<f64>() / n).sqrt();
    (rms, d.iter().fold(0.0, |m, x| m.max(x.abs())))
}

/// RMS difference of the angles \[deg\] over every run and joint between the
/// model as fitted and the model with effect `k`'s table replaced by
/// `export`.
fn angle_loss(
    campaign: &Campaign,
    trajectories: &[Option<Trajectory>],
    effects: &[Effect],
    k: usize,
    export: &TorqueTable<f64>,
) -> Option<f64> {
    let mut swapped = effects.to_vec();
    let host =
        |t: &Option<Table<f64>>| t.as_ref().and_then(|t| HostTable::new(t.xs(), t.ys()).ok());
    swapped.get_mut(k)?.law = Law::TorqueTable(HostTorqueTable {
        angle: host(&export.angle),
        rate: host(&export.rate),
    });
    let (mut sum, mut n) = (0.0, 0usize);
    for (i, traj) in trajectories.iter().enumerate() {
        let a = traj.as_ref()?;
        let b = campaign.simulate(i, &swapped).ok()?;
        for (pa, pb) in a.phi_deg.iter().zip(&b.phi_deg) {
            for (x, y) in pa.iter().zip(pb) {
                sum += (x - y).powi(2);
                n += 1;
            }
        }
    }
    (n > 0).then(|| (sum / n as f64).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 1500 samples of a stroke, the rate peaking at 3e+02 deg/s.
    fn samples(f: impl Fn(f64, f64) -> f64) -> Vec<TorqueSample> {
        crate::analysis::diagnose::residual_torque::synthetic_stroke(1500, 300.0, 1.0, 1, f)
    }

    fn host_table(n: usize) -> HostTorqueTable {
        let xs: Vec<f64> = (0..n).map(|i| 180.0 * i as f64 / (n - 1) as f64).collect();
        let ys: Vec<f64> = xs
            .iter()
            .map(|x| 0.2 * (-((x - 100.0) / 12.0).powi(2)).exp())
            .collect();
        HostTorqueTable {
            angle: HostTable::new(&xs, &ys).ok(),
            rate: None,
        }
    }

    #[test]
    fn given_a_small_table_then_it_is_exported_as_it_is() {
        let host = host_table(6);
        let s = samples(|p, v| host.torque(p.to_radians(), v.to_radians()));
        let (t, compressed) = compress(&host, &s, -1.0).unwrap();
        assert!(!compressed);
        assert_eq!(t.angle.unwrap().xs(), host.angle.unwrap().xs());
        assert_eq!(torque_loss(&host, &t, &s), (0.0, 0.0));
    }

    #[test]
    fn given_a_dense_table_then_eight_knots_follow_its_bump() {
        let host = host_table(24);
        let s = samples(|p, v| host.torque(p.to_radians(), v.to_radians()));
        let (t, compressed) = compress(&host, &s, -1.0).unwrap();
        assert!(compressed);
        let f = t.angle.unwrap();
        assert!(
            f.xs().len() <= TABLE_MAX_KNOTS && f.xs().len() >= 5,
            "{f:?}"
        );
        let (rms, max) = torque_loss(&host, &t, &s);
        // Eight knots against a 0.2 N·m bump sampled at 24 points: the
        // error is a few per cent of its height.
        assert!(rms < 0.01 && max < 0.03, "rms {rms} max {max}");
        // Even knots of the same count do worse than placed ones.
        let even: Vec<f64> = (0..8).map(|i| 180.0 * i as f64 / 7.0).collect();
        let ys: Vec<f64> = even
            .iter()
            .map(|&x| host.torque(x.to_radians(), 0.0))
            .collect();
        let naive = TorqueTable {
            angle: Table::new(&even, &ys).ok(),
            rate: None,
        };
        assert!(torque_loss(&host, &naive, &s).0 > rms);
    }
}
