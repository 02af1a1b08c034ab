//! The reference sensor model of `docs/spec/physics.md` section 7: a 14-bit
//! absolute encoder per joint with white noise before quantisation, and an
//! ideal latch switch.
//!
//! Reading = true angle + `encoder_offset` + N(0, σ²), rounded to the nearest
//! multiple of 360°/16384, not wrapped. Noise continues after a joint latches.
//! The noise comes from a ChaCha8 generator seeded with the run's seed and
//! drawn sample by sample, joint by joint, so the same seed gives the same
//! file byte for byte on every machine.

use crate::data::run::Run;
use crate::simulate::trajectory::Trajectory;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

/// Encoder resolution of a 14-bit absolute encoder \[deg\]: one count of the
/// AS5047P ([`deploywatch_core::monitor::encoder::STEP_DEG`]).
pub const RESOLUTION_DEG: f64 = deploywatch_core::monitor::encoder::STEP_DEG;

/// Standard deviation of the reference encoder noise \[deg\].
pub const NOISE_SIGMA_DEG: f64 = 0.02;

/// The encoder and switch model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SensorModel {
    /// White noise σ added before quantisation \[deg\]; 0 for none.
    pub noise_sigma_deg: f64,
    /// Quantisation step \[deg\]; 0 for none.
    pub resolution_deg: f64,
}

impl SensorModel {
    /// The reference sensor: σ = 0.02°, 14 bits.
    pub const REFERENCE: SensorModel = SensorModel {
        noise_sigma_deg: NOISE_SIGMA_DEG,
        resolution_deg: RESOLUTION_DEG,
    };
    /// A perfect sensor: the true angle.
    pub const IDEAL: SensorModel = SensorModel {
        noise_sigma_deg: 0.0,
        resolution_deg: 0.0,
    };

    /// One reading of a true angle `deg` with `noise` already drawn.
    #[inline]
    pub fn read(&self, deg: f64, noise: f64) -> f64 {
        let x = deg + noise;
        if self.resolution_deg > 0.0 {
            (x / self.resolution_deg).round() * self.resolution_deg
        } else {
            x
        }
    }
}

/// Measures a simulated trajectory: the run a rig would have recorded.
///
/// `offsets_deg` are the `encoder_offset` effects per joint. The run's
/// metadata is left for the caller to fill in (mechanism, source, ...).
pub fn measure(traj: &Trajectory, offsets_deg: &[f64], sensor: &SensorModel, seed: u64) -> Run {
    let n = traj.joints();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let normal = Normal::new(0.0, sensor.noise_sigma_deg.max(0.0)).ok();
    let mut phi = vec![Vec::with_capacity(traj.t_s.len()); n];
    for i in 0..traj.t_s.len() {
        for j in 0..n {
            let noise = match normal {
                Some(d) if sensor.noise_sigma_deg > 0.0 => d.sample(&mut rng),
                _ => 0.0,
            };
            let b = offsets_deg.get(j).copied().unwrap_or(0.0);
            phi[j].push(sensor.read(traj.phi_deg[j][i] + b, noise));
        }
    }
    Run {
        metadata: Vec::new(),
        t_s: traj.t_s.clone(),
        phi_deg: phi,
        latch: traj.latched.clone(),
        extra: Vec::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantises_to_the_nearest_step_without_wrapping() {
        let s = SensorModel::REFERENCE;
        assert_eq!(
            s.read(180.0 + 0.6 * RESOLUTION_DEG, 0.0),
            180.0 + RESOLUTION_DEG
        );
        assert_eq!(s.read(-0.4 * RESOLUTION_DEG, 0.0), 0.0);
        assert_eq!(SensorModel::IDEAL.read(1.234, 0.0), 1.234);
    }

    #[test]
    fn same_seed_same_readings() {
        let traj = Trajectory {
            t_s: vec![0.0, 0.01, 0.02],
            phi_deg: vec![vec![10.0, 9.0, 8.0]],
            rate_deg_s: vec![vec![0.0; 3]],
            latched: vec![vec![false; 3]],
            latch_s: vec![None],
            end_s: 0.02,
            stats: Default::default(),
            past_stowed: Vec::new(),
        };
        let a = measure(&traj, &[0.0], &SensorModel::REFERENCE, 7);
        let b = measure(&traj, &[0.0], &SensorModel::REFERENCE, 7);
        let c = measure(&traj, &[0.0], &SensorModel::REFERENCE, 8);
        assert_eq!(a, b);
        assert_ne!(a, c);
    }
}
