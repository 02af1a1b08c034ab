//! On-board torque margin of the remaining stroke and the latch / stall
//! prediction (`physics.md` §9, energy form of seed 000 Eqs. 17–21).
//!
//! # Energy balance of the remaining stroke
//! For a joint at `x₀ = |φ|` \[rad\] moving with kinetic energy `K` \[J\], the
//! energy left when it reaches `x < x₀` is, in a one-joint model,
//!
//! ```text
//! E(x) = K_eff + ∫ₓ^{x₀} T_s(θ) dθ − T_C (x₀ − x) − f ∫ₓ^{x₀} ω dθ          [J]
//! ```
//! `T_s` the unfolding spring magnitude (all hinges), `T_C`, `f` the friction
//! estimate. The joint latches when `E(x) > 0` all the way to the capture
//! angle `x_c` (below it a tape spring's snap-through torque, tens of N·m,
//! completes the latch whatever the friction; `x_c = 0` for a linear spring).
//! `K_eff = K` when the joint moves towards the latch; when it moves away it
//! first travels `Δ = K/(T_s + T_C)` further out and comes back, which leaves
//! `K_eff = K (T_s − T_C)/(T_s + T_C)`.
//!
//! `E` is marched over [`NODES`] equal steps from `x₀` to `x_c`, with the
//! viscous loss of a step taken at the speed of its start, `ω = √(2E/I)`.
//! The monitor passes the articulated inertia `I = 1/(M⁻¹)_jj` over the
//! free joints and `K = ½ I ω²`: all the kinetic energy of the joint's
//! motion, the outer panels' share included. The latch impacts of the other
//! joints destroy part of it (`physics.md` §5), and their reactions can hold
//! the joint back, so the balance errs towards a latch: a stall it predicts
//! is a safe verdict, a latch is checked by the rollouts
//! ([`crate::monitor::rollout`]). Its variance follows
//! from the friction covariance and a relative spread of the spring energy:
//!
//! ```text
//! σ²_E = W_C² σ²_TC + W_v² σ²_f + 2 W_C W_v σ_TC,f + (σ_κ E_s)² + σ²_K,
//! W_C = x₀ − x,  W_v = ∫ ω dθ
//! ```
//! The joint latches when `T_C < T*`, `T* = min_x A(x)/W_C(x)` with `A`
//! the energy at `x` without the Coulomb loss; with `T_C ~ N(T̂_C, σ²)`
//! truncated below at `L` (friction is never negative, nor smaller than the
//! friction torque the observer sees now, [`MarginInput::coulomb_lower_nm`]):
//!
//! ```text
//! P(latch) = [Φ((T* − T̂_C)/σ) − Φ((L − T̂_C)/σ)] / [1 − Φ((L − T̂_C)/σ)]
//! σ² = σ²_TC + σ²_A / W_C²
//! ```
//! The time to latch sums
//! `Δx / ½(ω_i + ω_{i+1})` over the steps.
//!
//! # Margin with uncertainty factors
//! ```text
//! TM = (E_s / FS_spring + max(K_eff, 0) / FS_kinetic)
//!      / (FS_coulomb T_C W_C + FS_viscous f W_v + max(−K_eff, 0) + FS_latch W_eng) − 1
//! ```
//! [×100 %] over the whole remaining stroke `[x_c, x₀]`. `W_eng` is the
//! work still ahead to climb a physical latch's entry ramp (0 for the ideal
//! latch), which the march also loses at its end; the march then ends at
//! the crest if it lies beyond `x_c` ([`crate::monitor::latch_margin`]).
//! The factors default to 1
//! (a best estimate); the presets take the NASA-STD-5017 and ECSS-E-ST-33-01C
//! factors from [`crate::monitor::standards`] (listed in `docs/margin.md`).

use crate::monitor::latch_margin::Engagement;
use crate::monitor::standards;
use crate::physics::spring::{Branch, Spring};

/// Steps of the energy march over the remaining stroke.
pub const NODES: usize = 6;

/// Largest margin reported [%]: a joint with no resistance left has an
/// unbounded margin, reported as this value.
pub const MARGIN_CAP_PCT: f32 = 10_000.0;

/// Uncertainty factors applied to each energy before the margin ratio
/// (NASA-STD-5017B Eq. 4-1 / ECSS-E-ST-33-01C clause 4.7.5 style).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct UncertaintyFactors {
    /// Divides the spring (driving) energy \[1\].
    pub spring: f32,
    /// Divides the kinetic energy already in the joint \[1\].
    pub kinetic: f32,
    /// Multiplies the Coulomb friction energy \[1\].
    pub coulomb: f32,
    /// Multiplies the viscous friction energy \[1\].
    pub viscous: f32,
    /// Multiplies the physical latch's engagement energy still ahead \[1\]
    /// ([`crate::monitor::latch_margin`]; the standards' "variable" /
    /// "other forces" factor in the presets, `docs/margin.md`).
    pub latch: f32,
}

impl UncertaintyFactors {
    /// All factors 1: the best-estimate margin.
    pub const UNITY: Self = UncertaintyFactors {
        spring: 1.0,
        kinetic: 1.0,
        coulomb: 1.0,
        viscous: 1.0,
        latch: 1.0,
    };

    /// ECSS-E-ST-33-01C ([`crate::monitor::standards`]): the driving spring
    /// unfactored, as `deploywatch margin` takes it (the table's spring
    /// factor is a resisting spring's; the driving one enters at its
    /// minimum), inertia divides the kinetic energy, friction multiplies
    /// both friction energies.
    pub const ECSS_E_ST_33_01C: Self = UncertaintyFactors {
        spring: 1.0,
        kinetic: standards::ECSS_E_ST_33_01C_INERTIA as f32,
        coulomb: standards::ECSS_E_ST_33_01C_FRICTION as f32,
        viscous: standards::ECSS_E_ST_33_01C_FRICTION as f32,
        latch: standards::ECSS_E_ST_33_01C_OTHER as f32,
    };

    /// NASA-STD-5017B ([`crate::monitor::standards`]): the driving spring
    /// unfactored (the standard factors the resistances), inertia
    /// ("acceleration") divides the kinetic energy, friction ("variable")
    /// multiplies both friction energies.
    pub const NASA_STD_5017: Self = UncertaintyFactors {
        spring: 1.0,
        kinetic: standards::NASA_STD_5017B_ACCELERATION as f32,
        coulomb: standards::NASA_STD_5017B_VARIABLE as f32,
        viscous: standards::NASA_STD_5017B_VARIABLE as f32,
        latch: standards::NASA_STD_5017B_VARIABLE as f32,
    };

    /// True when every factor is finite and ≥ 1 is not required, only > 0.
    pub(crate) fn is_valid(&self) -> bool {
        [
            self.spring,
            self.kinetic,
            self.coulomb,
            self.viscous,
            self.latch,
        ]
        .iter()
        .all(|f| f.is_finite() && *f > 0.0)
    }
}

impl Default for UncertaintyFactors {
    fn default() -> Self {
        Self::UNITY
    }
}

/// The state of one joint the margin is computed from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MarginInput {
    /// `x₀ = |φ|` \[rad\].
    pub angle_abs_rad: f32,
    /// `|ω|` [rad/s].
    pub rate_abs_rad_s: f32,
    /// True when the joint moves towards the latch (`φ ω < 0`).
    pub towards_latch: bool,
    /// Inertia `I` [kg·m²] (> 0): the articulated inertia `1/(M⁻¹)_jj`.
    pub inertia_kgm2: f32,
    /// Variance of the rate [rad²/s²].
    pub rate_var: f32,
    /// Capture angle `x_c` \[rad\].
    pub capture_rad: f32,
    /// Friction estimate `T_C` [N·m].
    pub coulomb_nm: f32,
    /// Friction estimate `f` [N·m·s/rad].
    pub viscous_nms: f32,
    /// Variance of `T_C`.
    pub coulomb_var: f32,
    /// A lower bound of `T_C` from the friction torque seen now [N·m]
    /// (0 for none): the estimate's distribution is truncated there.
    pub coulomb_lower_nm: f32,
    /// Factor on the nominal spring curve, `1 + κ̂` \[1\].
    pub spring_scale: f32,
    /// Standard deviation of that factor \[1\].
    pub spring_sd_rel: f32,
    /// Variance of `f`.
    pub viscous_var: f32,
    /// Covariance of `T_C` and `f`.
    pub cov: f32,
    /// The joint's physical latch ([`Engagement::IDEAL`] for the ideal one).
    pub latch: Engagement,
}

/// Settings of the prediction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MarginSettings {
    /// Uncertainty factors of the reported margin.
    pub factors: UncertaintyFactors,
    /// Floor of the energy standard deviation \[J\].
    pub energy_sd_floor_j: f32,
}

/// The margin and the prediction of one joint.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MarginResult {
    /// Torque margin of the remaining stroke, energy form, with the
    /// configured factors [%], capped at [`MARGIN_CAP_PCT`].
    pub margin_pct: f32,
    /// Probability that the joint reaches its capture angle [0, 1].
    pub latch_probability: f32,
    /// Predicted time to the capture angle \[s\], `None` when the best
    /// estimate stalls.
    pub time_to_latch_s: Option<f32>,
    /// The best estimate reaches a physical latch's crest without the
    /// entry ramp's work and not with it: the plunger stops the joint
    /// ([`crate::monitor::latch_margin`]).
    pub stops_on_ramp: bool,
}

/// Standard normal distribution function `Φ(z) = ½ erfc(−z/√2)`.
pub fn normal_cdf(z: f32) -> f32 {
    0.5 * libm::erfcf(-z * core::f32::consts::FRAC_1_SQRT_2)
}

/// `P(X < x | X ≥ lower)` for `X ~ N(mean, sd²)`.
pub fn truncated_below_cdf(x: f32, mean: f32, sd: f32, lower: f32) -> f32 {
    if !(x > lower) {
        return 0.0;
    }
    let fl = normal_cdf((lower - mean) / sd);
    let fx = normal_cdf((x - mean) / sd);
    let tail = 1.0 - fl;
    if tail > 1e-9 {
        ((fx - fl) / tail).clamp(0.0, 1.0)
    } else {
        // The bound sits far above the estimate: the bound decides.
        0.0
    }
}

/// Evaluates the energy balance of the remaining stroke of one joint with
/// spring `spring` (the joint's nominal spring, all hinges).
pub fn evaluate(spring: &Spring<f32>, x: &MarginInput, s: &MarginSettings) -> MarginResult {
    let x0 = x.angle_abs_rad;
    let xc = x.latch.march_end(x.capture_rad.max(0.0));
    let tc = x.coulomb_nm.max(0.0);
    let fv = x.viscous_nms.max(0.0);
    let inertia = x.inertia_kgm2.max(1e-6);
    if !(x0 > xc) {
        // Inside the capture zone: the spring completes the latch.
        return MarginResult {
            margin_pct: MARGIN_CAP_PCT,
            latch_probability: 1.0,
            time_to_latch_s: Some(0.0),
            stops_on_ramp: false,
        };
    }
    let w = x.rate_abs_rad_s;
    let k = 0.5 * inertia * w * w;
    // σ_K from the rate variance: dK = I ω dω.
    let var_k = inertia * inertia * w * w * x.rate_var.max(0.0);
    let k_eff = if x.towards_latch {
        k
    } else {
        moving_away(spring, x, k, tc)
    };
    let stroke = Stroke {
        x0,
        xc,
        tc,
        fv,
        inertia,
        k_eff,
        var_k,
    };
    let mut m = march(spring, x, s, &stroke);
    let w_eng = x.latch.work_j(xc, x0);
    let stops_on_ramp = m.climb_ramp(w_eng, tc, x0 <= x.latch.foot_rad());
    let drive = m.e_s / s.factors.spring + k_eff.max(0.0) / s.factors.kinetic;
    let resist = s.factors.coulomb * tc * m.w_c
        + s.factors.viscous * fv * m.w_v
        + (-k_eff).max(0.0)
        + s.factors.latch * w_eng;
    let margin_pct = if resist > 1e-9 {
        ((drive / resist - 1.0) * 100.0).clamp(-100.0, MARGIN_CAP_PCT)
    } else {
        MARGIN_CAP_PCT
    };
    // P(T_C < T*) for T_C ~ N(T̂_C, σ²) truncated to T_C ≥ L (friction is
    // never negative, and never below the torque it exerts now).
    let sd = crate::physics::real::sqrtf((x.coulomb_var.max(0.0) + m.t_star_var).max(1e-12));
    let lower = x.coulomb_lower_nm.max(0.0);
    let p = truncated_below_cdf(m.t_star, tc, sd, lower);
    MarginResult {
        margin_pct: if margin_pct.is_finite() {
            margin_pct
        } else {
            0.0
        },
        latch_probability: if p.is_finite() {
            p.clamp(0.0, 1.0)
        } else {
            0.5
        },
        time_to_latch_s: if m.stalled || !m.t_total.is_finite() {
            None
        } else {
            Some(m.t_total)
        },
        stops_on_ramp,
    }
}

/// `K_eff` of a joint moving away from the latch with kinetic energy `k`
/// \[J\] against the Coulomb torque `tc` [N·m]: it first travels
/// `Δ = K/(T_s + T_C)` further out and comes back, which leaves
/// `K (T_s − T_C)/(T_s + T_C)`.
fn moving_away(spring: &Spring<f32>, x: &MarginInput, k: f32, tc: f32) -> f32 {
    let ts = x.spring_scale.max(0.0) * spring.magnitude(x.angle_abs_rad, Branch::Unfold);
    let den = ts + tc;
    if den > 1e-6 {
        k * (ts - tc) / den
    } else {
        0.0
    }
}

/// The remaining stroke of a joint, as [`evaluate`] marches it.
struct Stroke {
    /// `x₀` and `x_c` \[rad\].
    x0: f32,
    xc: f32,
    /// `T_C` [N·m] and `f` [N·m·s/rad], not negative.
    tc: f32,
    fv: f32,
    /// `I` [kg·m²].
    inertia: f32,
    /// `K_eff` \[J\] and the variance of `K` \[J²\].
    k_eff: f32,
    var_k: f32,
}

/// What the march over the remaining stroke adds up.
struct March {
    /// Spring energy released `E_s` \[J\].
    e_s: f32,
    /// `W_C = x₀ − x_c` \[rad\] and `W_v = ∫ ω dθ` [rad²/s].
    w_c: f32,
    w_v: f32,
    /// The most demanding node's threshold `T*` [N·m] and its variance.
    t_star: f32,
    t_star_var: f32,
    /// Time to the capture angle \[s\] (over the steps the joint moves).
    t_total: f32,
    /// The energy ran out before the capture angle.
    stalled: bool,
    /// `E` left at the end of the march \[J\].
    e_end: f32,
}

impl March {
    /// Takes a physical latch's entry-ramp work still ahead `w_eng` \[J\]
    /// off at the end of the march (`latch_margin`), `tc` the Coulomb
    /// torque [N·m]; true when the joint stops on the ramp: the march
    /// reaches the crest without the ramp's work and not with it, or the
    /// joint is on the ramp already (`on_ramp`) and stalls. An exact no-op
    /// for the ideal latch (`w_eng` = 0: the threshold is the last node's,
    /// a stall at the end is already one; no joint is on a ramp of no
    /// width beyond the capture angle).
    fn climb_ramp(&mut self, w_eng: f32, tc: f32, on_ramp: bool) -> bool {
        let reaches = !self.stalled && self.e_end > 0.0;
        self.e_end -= w_eng;
        let stops = self.e_end <= 0.0;
        self.stalled |= stops;
        let threshold = (self.e_end + tc * self.w_c) / self.w_c;
        if threshold < self.t_star {
            self.t_star = threshold;
        }
        (reaches && stops) || (on_ramp && self.stalled)
    }
}

/// Marches `E` over [`NODES`] equal steps from `x₀` to `x_c`, with the
/// viscous loss of a step taken at the speed of its start.
fn march(spring: &Spring<f32>, x: &MarginInput, s: &MarginSettings, st: &Stroke) -> March {
    let (tc, fv, inertia) = (st.tc, st.fv, st.inertia);
    let step = (st.x0 - st.xc) / NODES as f32;
    let mut e = st.k_eff;
    let mut e_s = 0.0f32;
    let mut w_c = 0.0f32;
    let mut w_v = 0.0f32;
    // The joint latches when T_C stays below T*_i = A_i / W_C,i at every
    // node, A_i the energy there without the Coulomb loss; the most
    // demanding node sets the threshold and its spread.
    let mut t_star = f32::INFINITY;
    let mut t_star_var = 0.0f32;
    let mut t_total = 0.0f32;
    let mut stalled = false;
    let mut omega = crate::physics::real::sqrtf(2.0 * e.max(0.0) / inertia);
    let mut hi = st.x0;
    for i in 0..NODES {
        let lo = if i + 1 == NODES {
            st.xc
        } else {
            st.x0 - (i + 1) as f32 * step
        };
        let dx = hi - lo;
        let gain = x.spring_scale.max(0.0) * spring.release(lo, hi);
        e_s += gain;
        w_c += dx;
        w_v += omega * dx;
        e += gain - tc * dx - fv * omega * dx;
        if w_c > 0.0 {
            let a = e + tc * w_c;
            let threshold = a / w_c;
            if threshold < t_star {
                t_star = threshold;
                // Spread of A (viscous, spring, kinetic) in Coulomb units.
                let var_a = w_v * w_v * x.viscous_var.max(0.0)
                    + (x.spring_sd_rel * e_s) * (x.spring_sd_rel * e_s)
                    + st.var_k
                    + s.energy_sd_floor_j * s.energy_sd_floor_j;
                t_star_var = var_a / (w_c * w_c);
            }
        }
        let omega_next = crate::physics::real::sqrtf(2.0 * e.max(0.0) / inertia);
        if e <= 0.0 {
            stalled = true;
        } else {
            let mean = 0.5 * (omega + omega_next);
            t_total += if mean > 1e-9 {
                dx / mean
            } else {
                f32::INFINITY
            };
        }
        omega = omega_next;
        hi = lo;
    }
    March {
        e_s,
        w_c,
        w_v,
        t_star,
        t_star_var,
        t_total,
        stalled,
        e_end: e,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn linear() -> Spring<f32> {
        Spring::Linear {
            preload_nm: 1.0,
            stiffness_nm_per_rad: 0.5,
            count: 1.0,
        }
    }

    fn input(tc: f32) -> MarginInput {
        MarginInput {
            angle_abs_rad: core::f32::consts::FRAC_PI_2,
            rate_abs_rad_s: 0.0,
            towards_latch: true,
            inertia_kgm2: 1.0,
            rate_var: 0.0,
            capture_rad: 0.0,
            coulomb_nm: tc,
            viscous_nms: 0.0,
            coulomb_var: 0.01,
            coulomb_lower_nm: 0.0,
            spring_scale: 1.0,
            spring_sd_rel: 0.0,
            viscous_var: 1e-6,
            cov: 0.0,
            latch: Engagement::IDEAL,
        }
    }

    const SET: MarginSettings = MarginSettings {
        factors: UncertaintyFactors::UNITY,
        energy_sd_floor_j: 1e-3,
    };

    #[test]
    fn margin_is_the_energy_ratio() {
        // E_D = 1·π/2 + ½·0.5·(π/2)² = 2.1875 J; T_C = 1 → E_R = π/2.
        let r = evaluate(&linear(), &input(1.0), &SET);
        let ed = core::f32::consts::FRAC_PI_2 + 0.25 * core::f32::consts::FRAC_PI_2.powi(2);
        let want = (ed / core::f32::consts::FRAC_PI_2 - 1.0) * 100.0;
        assert!(
            (r.margin_pct - want).abs() < 0.01,
            "{} vs {want}",
            r.margin_pct
        );
        assert!(r.latch_probability > 0.99);
        assert!(r.time_to_latch_s.is_some());
        // Friction beyond the spring: stall.
        let r = evaluate(&linear(), &input(2.0), &SET);
        assert!(r.margin_pct < 0.0);
        assert!(r.latch_probability < 0.01);
        assert!(r.time_to_latch_s.is_none());
        // Factors scale the ratio.
        let mut s = SET;
        s.factors.coulomb = 2.0;
        let r2 = evaluate(&linear(), &input(1.0), &s);
        assert!(
            (r2.margin_pct - ((ed / (2.0 * core::f32::consts::FRAC_PI_2) - 1.0) * 100.0)).abs()
                < 0.01
        );
        // Uncertain friction near the threshold T* = 1.39 N·m: undecided,
        // until the friction torque seen bounds T_C above T*.
        let mut u = input(1.2);
        u.coulomb_var = 0.5 * 0.5;
        let r = evaluate(&linear(), &u, &SET);
        assert!(
            r.latch_probability > 0.5 && r.latch_probability < 0.9,
            "{}",
            r.latch_probability
        );
        u.coulomb_lower_nm = 1.45;
        assert_eq!(evaluate(&linear(), &u, &SET).latch_probability, 0.0);
    }

    #[test]
    fn truncated_normal() {
        assert!((truncated_below_cdf(0.0, 0.0, 1.0, -100.0) - 0.5).abs() < 1e-6);
        assert_eq!(truncated_below_cdf(1.0, 0.0, 1.0, 2.0), 0.0);
        // Half the mass below the mean removed: P(X < mean | X ≥ mean − 1σ).
        let p = truncated_below_cdf(0.0, 0.0, 1.0, -1.0);
        assert!(
            (p - (0.5 - 0.158_655_25) / (1.0 - 0.158_655_25)).abs() < 1e-5,
            "{p}"
        );
    }

    #[test]
    fn time_to_latch_of_a_constant_net_torque() {
        // Spring 1 N·m constant, no friction, I = 1: x = ½ t² → t = √(2 x₀).
        let s = Spring::Linear {
            preload_nm: 1.0,
            stiffness_nm_per_rad: 0.0,
            count: 1.0,
        };
        let r = evaluate(&s, &input(0.0), &SET);
        let want = crate::physics::real::sqrtf(2.0 * core::f32::consts::FRAC_PI_2);
        let got = r.time_to_latch_s.unwrap();
        assert!((got - want).abs() < 0.08 * want, "{got} vs {want}");
    }

    #[test]
    fn moving_away_costs_energy() {
        let mut a = input(1.2);
        a.rate_abs_rad_s = 1.0;
        a.towards_latch = true;
        let towards = evaluate(&linear(), &a, &SET);
        a.towards_latch = false;
        let away = evaluate(&linear(), &a, &SET);
        assert!(away.margin_pct < towards.margin_pct);
    }
}
