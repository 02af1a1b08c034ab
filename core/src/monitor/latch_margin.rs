//! The physical latch's engagement in the on-board margin and prediction
//! (`physics.md` §10.3, `docs/margin.md` "The latch's engagement").
//!
//! A joint with a physical latch must climb the ball plunger's entry ramp
//! before its crest: a resistance of the stroke's last part. The monitor
//! carries the three figures of it the energy margin needs ([`Engagement`];
//! the whole law of `physics::latch_contact` is not compiled into the
//! monitor, and the entry torque, which only the torque form uses, stays on
//! the host):
//!
//! ```text
//! E_eng = P0 h + ½ k_p h²                    [J]    engagement energy
//! u_c, w_e = h / (r_p tan α_e)               [rad]  crest and entry-ramp width
//! ```
//!
//! In the energy balance of the remaining stroke ([`crate::monitor::margin`])
//! the march ends at the crest (past it the hold ramp and the magnet pull the
//! joint in) or at the capture angle, whichever is further out, and loses
//! the ramp's work still ahead at its end: all of `E_eng` while the joint is
//! short of the ramp, its share of the ramp's width left once on it (the
//! ramp's torque, rising towards the crest, is taken as its mean there: the
//! flash of the monitor is spent where the margin is decided, outside the
//! ramp). The ramp, a degree or two wide, lies in the march's last steps;
//! the speeds of the viscous loss and of the time to the latch leave it out.
//! The margin counts that work as a resistance with the factor
//! [`crate::monitor::margin::UncertaintyFactors::latch`]. A joint whose
//! best-estimate march reaches the crest without the ramp's work and not
//! with it, or that is on the ramp already and stalls, and that is
//! predicted to stall, **stops on the ramp**
//! (`Prediction::RampStop`, [`crate::monitor::predictor`]). An ideal latch
//! ([`Engagement::IDEAL`], all zero) changes nothing: every term it adds is
//! an exact `+ 0`.

/// The figures of a joint's physical latch the margin needs (all zero for
/// the ideal latch of `physics.md` §5).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Engagement {
    /// `E_eng = P0 h + ½ k_p h²`: energy to climb the entry ramp \[J\].
    pub energy_j: f32,
    /// `u_c`: travel from the stop of the crest \[rad\].
    pub crest_rad: f32,
    /// `w_e`: angular width of the entry ramp \[rad\].
    pub ramp_rad: f32,
}

impl Engagement {
    /// The ideal latch: no plunger to climb.
    pub const IDEAL: Self = Engagement {
        energy_j: 0.0,
        crest_rad: 0.0,
        ramp_rad: 0.0,
    };

    /// True for the ideal latch (no engagement energy).
    pub fn is_ideal(&self) -> bool {
        !(self.energy_j > 0.0)
    }

    /// True when every figure is finite and ≥ 0 (a ramp of no width adds
    /// no work: [`Engagement::work_j`]).
    pub(crate) fn is_valid(&self) -> bool {
        [self.energy_j, self.crest_rad, self.ramp_rad]
            .iter()
            .all(|v| v.is_finite() && *v >= 0.0)
    }

    /// `u_c + w_e`: travel of the entry ramp's foot \[rad\].
    pub fn foot_rad(&self) -> f32 {
        self.crest_rad + self.ramp_rad
    }

    /// Work of the entry ramp against a joint going from travel `hi` to
    /// `lo < hi` \[J\]: `E_eng` times the share of the ramp's width in
    /// `[lo, hi]` (all of it when `[lo, hi]` spans the ramp). 0 for the
    /// ideal latch (a ramp of no width).
    pub(crate) fn work_j(&self, lo: f32, hi: f32) -> f32 {
        // Plain comparisons rather than `f32::max`/`min` (their NaN rules
        // cost flash on the Cortex-M4F): a NaN bound gives 0.
        let foot = self.foot_rad();
        let a = if lo > self.crest_rad {
            lo
        } else {
            self.crest_rad
        };
        let b = if hi < foot { hi } else { foot };
        if !(b > a) {
            return 0.0;
        }
        self.energy_j * (b - a) / self.ramp_rad
    }

    /// Where the energy march of the remaining stroke ends \[rad\]: the
    /// capture angle `x_c`, or the crest when it lies further out.
    /// The same capture angle for the ideal latch (crest 0, `x_c ≥ 0`).
    pub(crate) fn march_end(&self, capture_rad: f32) -> f32 {
        if self.crest_rad > capture_rad {
            self.crest_rad
        } else {
            capture_rad
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The plunger of `data/mechanisms/one_panel_physical_latch.toml`:
    /// P0 = 10 N, k_p = 60 N/mm, h = 0.8 mm, r_p = 40 mm, α_e = 30°,
    /// crest 0.6°.
    fn one_panel() -> Engagement {
        let (p0, kp, h, r_mm) = (10.0f64, 60.0, 0.8, 40.0);
        let rate = r_mm * 30f64.to_radians().tan(); // mm/rad
        Engagement {
            energy_j: ((p0 * h + 0.5 * kp * h * h) / 1000.0) as f32,
            crest_rad: 0.6f64.to_radians() as f32,
            ramp_rad: (h / rate) as f32,
        }
    }

    #[test]
    fn ramp_work_is_the_engagement_spread_over_the_ramp() {
        let l = one_panel();
        assert!(l.is_valid());
        // Whole ramp: E_eng = 10·0.8 + 30·0.64 = 27.2 N·mm.
        let w = l.work_j(0.0, 1.0);
        assert!((w - 0.0272).abs() < 1e-6, "{w}");
        // Split anywhere, the parts add up; nothing outside the ramp.
        let mid = l.crest_rad + 0.3 * l.ramp_rad;
        let parts = l.work_j(0.0, mid) + l.work_j(mid, 1.0);
        assert!((parts - w).abs() < 1e-7);
        assert!((l.work_j(0.0, mid) - 0.3 * w).abs() < 1e-6);
        assert_eq!(l.work_j(l.foot_rad(), 1.0), 0.0);
        assert_eq!(l.work_j(0.0, l.crest_rad), 0.0);
    }

    #[test]
    fn ideal_latch_adds_nothing() {
        let l = Engagement::IDEAL;
        assert!(l.is_ideal() && l.is_valid());
        assert_eq!(l.work_j(0.0, 10.0), 0.0);
        assert_eq!(l.march_end(0.02), 0.02);
    }

    #[test]
    fn bad_figures_are_refused_and_never_panic() {
        let mut l = one_panel();
        l.energy_j = f32::NAN;
        assert!(!l.is_valid());
        let mut l = one_panel();
        l.crest_rad = -0.1;
        assert!(!l.is_valid());
        // A ramp of no width does no work.
        let mut l = one_panel();
        l.ramp_rad = 0.0;
        assert!(l.is_valid());
        assert_eq!(l.work_j(0.0, 1.0), 0.0);
        for x in [f32::NAN, f32::INFINITY, -1.0] {
            let mut l = one_panel();
            l.energy_j = x;
            let _ = l.work_j(0.0, 1.0);
        }
    }

    #[test]
    fn energy_march_counts_the_ramp_and_finds_the_stop_on_it() {
        use crate::monitor::margin::{evaluate, MarginInput, MarginSettings, UncertaintyFactors};
        use crate::physics::spring::Spring;
        // The panel of one_panel_physical_latch.toml at the top of a
        // rebound: 13° out, at rest, spring 1 + 0.5 φ N·m.
        let spring = Spring::Linear {
            preload_nm: 1.0,
            stiffness_nm_per_rad: 0.5,
            count: 1.0,
        };
        let l = one_panel();
        let x0 = 13f32.to_radians();
        let input = |tc: f32| MarginInput {
            angle_abs_rad: x0,
            rate_abs_rad_s: 0.0,
            towards_latch: true,
            inertia_kgm2: 0.64,
            rate_var: 0.0,
            capture_rad: 0.0,
            coulomb_nm: tc,
            viscous_nms: 0.0,
            coulomb_var: 1e-4,
            coulomb_lower_nm: 0.0,
            spring_scale: 1.0,
            spring_sd_rel: 0.0,
            viscous_var: 0.0,
            cov: 0.0,
            latch: l,
        };
        let mut set = MarginSettings {
            factors: UncertaintyFactors::UNITY,
            energy_sd_floor_j: 1e-3,
        };
        // By hand: the march ends at the crest u_c; E_D = ∫ (1 + 0.5 θ) dθ
        // over [u_c, x₀], E_R = T_C (x₀ − u_c) + E_eng (all of the ramp ahead).
        let c = l.crest_rad;
        let e_d = (x0 - c) + 0.25 * (x0 * x0 - c * c);
        for (tc, on_ramp, stalls) in [(0.9, false, false), (1.05, true, true), (1.2, false, true)] {
            let r = evaluate(&spring, &input(tc), &set);
            let want = (e_d / (tc * (x0 - c) + l.energy_j) - 1.0) * 100.0;
            assert!(
                (r.margin_pct - want).abs() < 0.05,
                "{tc}: {} vs {want}",
                r.margin_pct
            );
            assert_eq!(r.stops_on_ramp, on_ramp, "{tc}");
            assert_eq!(r.time_to_latch_s.is_none(), stalls, "{tc}");
        }
        // The factor weighs the engagement.
        set.factors.latch = 3.0;
        let r = evaluate(&spring, &input(0.9), &set);
        let want = (e_d / (0.9 * (x0 - c) + 3.0 * l.energy_j) - 1.0) * 100.0;
        assert!((r.margin_pct - want).abs() < 0.05);
        // An ideal latch: the march to 0 of margin.rs, no ramp stop.
        let mut ideal = input(1.05);
        ideal.latch = Engagement::IDEAL;
        let r = evaluate(&spring, &ideal, &set);
        let want = ((x0 + 0.25 * x0 * x0) / (1.05 * x0) - 1.0) * 100.0;
        assert!((r.margin_pct - want).abs() < 0.05);
        assert!(!r.stops_on_ramp);
        // At rest on the ramp (1.12° out, as latch_ramp_stop ends) against
        // more friction than the spring gives: it stops where it is, on the
        // ramp; beyond the ramp's foot the same stall is not on it.
        let on_ramp = MarginInput {
            angle_abs_rad: 1.12f32.to_radians(),
            ..input(1.05)
        };
        assert!(evaluate(&spring, &on_ramp, &set).stops_on_ramp);
        let short = MarginInput {
            angle_abs_rad: l.foot_rad() + 0.05,
            ..input(2.0)
        };
        let r = evaluate(&spring, &short, &set);
        assert!(r.time_to_latch_s.is_none() && !r.stops_on_ramp);
    }
}
