//! The physical latch of one joint (`docs/spec/physics.md` section 10, this
//! project's extension): a Hertzian stop, a ball-plunger detent and a
//! magnet, acting on the joint through the latch's travel from the stop.
//!
//! # Travel and torques
//! The joint arrives from the side of its stowed angle, `s = sign(φ_stowed)`.
//! The latch works on the **travel** `u = s φ` \[rad\]: positive while the
//! protrusion is short of the stop, 0 at the stop, negative inside it. A
//! torque `τ_u` that increases `u` is the joint torque `τ_φ = s τ_u`.
//!
//! # The stop (Hertz with Hunt–Crossley-type damping)
//! At radius `r_c` from the hinge the penetration is `δ = −u r_c` \[mm\]
//! (positive inside the stop) and
//!
//! ```text
//! F = k δ^1.5 + c δ^0.25 δ̇     [N], δ in mm, δ̇ in mm/s,
//! k [N/mm^1.5], c [N·s/mm^1.25]  (seed 000 §4.2, seed 001 §4.2)
//! ```
//!
//! only while `δ > 0`, and never pulling: the force applied is `max(F, 0)`.
//! `τ_u = F r_c` [N·m] pushes the joint back out of the stop. The elastic
//! part stores `V_c = k δ^2.5 / 2.5` [N·mm]; the rest dissipates.
//!
//! # The ball plunger
//! A ball pressed by a spring (`P = P0 + k_p x`, `x` its depression \[mm\])
//! sits on the protrusion's path at radius `r_p`. Coming in, the protrusion
//! pushes the ball in along the entry ramp (angle `α_e`) until the crest
//! `u_c`, where the ball is in by the stroke `h`; past the crest the ball
//! runs down the hold ramp (angle `α_h`) and pushes the protrusion towards
//! the stop. Depression along the travel:
//!
//! ```text
//! entry ramp  u_c < u ≤ u_c + w_e:  x = (u_c + w_e − u) r_p tan α_e,  w_e = h / (r_p tan α_e)
//! hold ramp   u_c − w_h ≤ u ≤ u_c:  x = (u − u_c + w_h) r_p tan α_h,  w_h = h / (r_p tan α_h)
//! elsewhere                         x = 0
//! V_p = P0 x + ½ k_p x²  [N·mm],  τ_u = −dV_p/du
//! ```
//!
//! The ball is frictionless, so the plunger is conservative: climbing the
//! entry ramp takes [`PhysicalLatch::engagement_energy`]; the largest
//! torque the hold ramp opposes to a return is
//! [`PhysicalLatch::holding_torque`].
//!
//! # The magnet
//! Over the last gap `g = u r_m` \[mm\] below its reach `g_r`, with the force
//! `F_m` at contact and decay length `g0`,
//!
//! ```text
//! F_m(g) = F_m0 [(1 + g/g0)^−2 − a] / (1 − a),  a = (1 + g_r/g0)^−2,   0 ≤ g < g_r
//! ```
//!
//! (zero at the reach, `F_m0` at contact, held at `F_m0` inside the stop),
//! pulling the joint towards the stop: `τ_u = −F_m r_m`.
//!
//! # The switch
//! The latch switch is closed while `u ≤ u_s`, its stated travel from the
//! stop ([`PhysicalLatch::switch_closed`]).
//!
//! Everything here is a pure function of `(φ, φ̇)`; it never panics (a
//! parameter set that [`PhysicalLatch::check`] refuses gives finite or NaN
//! numbers, never a panic).

use crate::physics::real::Real;

/// Millimetres per metre: the papers give the stop in mm, the chain is in m.
pub(crate) const MM_PER_M: f64 = 1000.0;

/// Smallest `1 + g/g0` the magnet law is evaluated at, where a frozen
/// segment is extended past its bounds (a step that crosses a mark).
const MAGNET_FLOOR: f64 = 0.1;

/// The stop: a Hertzian contact with Hunt–Crossley-type damping.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HertzStop<T> {
    /// `k` [N/mm^1.5] (seed 000 §4.2, seed 001 §4.2: 37,000).
    pub stiffness_n_per_mm1_5: T,
    /// `c` [N·s/mm^1.25] (seed 000 §4.2, seed 001 §4.2: 3.7).
    pub damping_ns_per_mm1_25: T,
    /// `r_c`: distance of the contact from the hinge axis \[m\].
    pub radius_m: T,
}

impl<T: Real> HertzStop<T> {
    /// The force of this contact law at penetration `δ` \[mm\] and its rate
    /// `δ̇` [mm/s]: zero while `δ ≤ 0`.
    pub(crate) fn force(&self, delta_mm: T, delta_dot_mm_s: T) -> StopForce<T> {
        if !(delta_mm > T::ZERO) {
            return StopForce {
                elastic_n: T::ZERO,
                raw_n: T::ZERO,
            };
        }
        let q = delta_mm.sqrt();
        let elastic_n = self.stiffness_n_per_mm1_5 * delta_mm * q;
        let raw_n = elastic_n + self.damping_ns_per_mm1_25 * q.sqrt() * delta_dot_mm_s;
        StopForce { elastic_n, raw_n }
    }

    /// The elastic energy `k δ^2.5 / 2.5` \[J\] at penetration `δ` \[mm\]
    /// (zero while `δ ≤ 0`).
    pub fn energy(&self, delta_mm: T) -> T {
        if !(delta_mm > T::ZERO) {
            return T::ZERO;
        }
        self.stiffness_n_per_mm1_5 * delta_mm * delta_mm * delta_mm.sqrt()
            / (T::of(2.5) * T::of(MM_PER_M))
    }
}

/// The ball plunger: a spring-loaded ball the protrusion climbs over.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plunger<T> {
    /// `P0`: the ball's spring force with the ball out \[N\].
    pub preload_n: T,
    /// `k_p`: the ball's spring rate [N/mm].
    pub stiffness_n_per_mm: T,
    /// `r_p`: distance of the ball from the hinge axis \[m\].
    pub radius_m: T,
    /// `h`: how far the ball is pushed in at the crest \[mm\].
    pub stroke_mm: T,
    /// `u_c`: travel from the stop at which the ball is on the crest \[rad\].
    pub crest_rad: T,
    /// `α_e`: angle of the entry ramp to the direction of travel \[rad\].
    pub entry_ramp_rad: T,
    /// `α_h`: angle of the hold ramp to the direction of travel \[rad\].
    pub hold_ramp_rad: T,
}

/// The magnet that pulls the protrusion over the last gap.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Magnet<T> {
    /// `F_m0`: attraction at contact \[N\].
    pub force_n: T,
    /// `g0`: decay length of the attraction \[mm\].
    pub decay_mm: T,
    /// `g_r`: gap beyond which the magnet does nothing \[mm\].
    pub reach_mm: T,
    /// `r_m`: distance of the magnet from the hinge axis \[m\].
    pub radius_m: T,
}

/// A pawl's figure beyond its spring and cam (those are the latch's
/// [`Plunger`]; `physics::pawl` holds its law).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pawl<T> {
    /// `T_b`: the torque the pawl carries at which it breaks [N·m].
    pub breaking_torque_nm: T,
}

/// What holds a physical latch's joint against a return.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Lock<T> {
    /// The ball plunger's hold ramp: a detent, climbable back over the
    /// crest (section 10.3).
    Detent,
    /// A pawl in its notch: a positive lock until it breaks (section 10.5,
    /// `physics::pawl`).
    Pawl(Pawl<T>),
}

/// The physical latch of one joint.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhysicalLatch<T> {
    /// `s`: +1 when the joint is stowed at a positive angle, −1 otherwise.
    pub side: T,
    /// The stop.
    pub stop: HertzStop<T>,
    /// The ball plunger.
    pub plunger: Plunger<T>,
    /// The magnet.
    pub magnet: Magnet<T>,
    /// `u_s`: the switch closes at this travel from the stop \[rad\].
    pub switch_travel_rad: T,
    /// What holds the joint against a return: the ball plunger's hold ramp
    /// (a detent, climbable back) or a pawl in its notch (a positive lock;
    /// the plunger is then the pawl's spring on its cam, `physics::pawl`).
    pub lock: Lock<T>,
}

/// What is wrong with a latch's parameters.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum LatchError {
    /// `side` is not ±1.
    Side,
    /// A parameter is negative or not finite.
    Negative(LatchParam),
    /// A parameter that must be positive (a radius, the magnet's decay,
    /// the pawl's breaking torque) is not.
    NotPositive(LatchParam),
    /// A ramp angle is not in (0°, 90°).
    Ramp(LatchParam),
}

/// A parameter of a [`PhysicalLatch`], as [`LatchError`] names it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum LatchParam {
    /// The stop's stiffness (N/mm^1.5).
    StopStiffness,
    /// The stop's damping (N·s/mm^1.25).
    StopDamping,
    /// The plunger's preload (N).
    PlungerPreload,
    /// The plunger's stiffness (N/mm).
    PlungerStiffness,
    /// The plunger's stroke (mm).
    PlungerStroke,
    /// The plunger's crest (rad).
    PlungerCrest,
    /// The magnet's force (N).
    MagnetForce,
    /// The magnet's reach (mm).
    MagnetReach,
    /// The switch travel (rad).
    SwitchTravel,
    /// The stop's radius (m).
    StopRadius,
    /// The plunger's radius (m).
    PlungerRadius,
    /// The magnet's radius (m).
    MagnetRadius,
    /// The magnet's decay length (mm).
    MagnetDecay,
    /// The pawl's breaking torque (N·m).
    PawlBreakingTorque,
    /// The plunger's entry ramp angle (rad).
    EntryRamp,
    /// The plunger's hold ramp angle (rad).
    HoldRamp,
}

impl LatchParam {
    /// The parameter's name in an error message ("stop radius").
    pub const fn name(self) -> &'static str {
        match self {
            LatchParam::StopStiffness => "stop stiffness",
            LatchParam::StopDamping => "stop damping",
            LatchParam::PlungerPreload => "plunger preload",
            LatchParam::PlungerStiffness => "plunger stiffness",
            LatchParam::PlungerStroke => "plunger stroke",
            LatchParam::PlungerCrest => "plunger crest",
            LatchParam::MagnetForce => "magnet force",
            LatchParam::MagnetReach => "magnet reach",
            LatchParam::SwitchTravel => "switch travel",
            LatchParam::StopRadius => "stop radius",
            LatchParam::PlungerRadius => "plunger radius",
            LatchParam::MagnetRadius => "magnet radius",
            LatchParam::MagnetDecay => "magnet decay length",
            LatchParam::PawlBreakingTorque => "pawl breaking torque",
            LatchParam::EntryRamp => "entry ramp",
            LatchParam::HoldRamp => "hold ramp",
        }
    }
}

impl core::fmt::Display for LatchError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            LatchError::Side => f.write_str("side must be +1 or -1"),
            LatchError::Negative(k) => write!(f, "{} must be a finite number >= 0", k.name()),
            LatchError::NotPositive(k) => write!(f, "{} must be a finite number > 0", k.name()),
            LatchError::Ramp(k) => {
                write!(f, "{} must be an angle between 0 and 90 deg", k.name())
            }
        }
    }
}

impl core::error::Error for LatchError {}

/// The points of the travel where the latch's torque law changes form: the
/// simulator locates each crossing as an event.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LatchMark {
    /// `u = 0`: contact onset and separation.
    Stop,
    /// `u = u_c`: the crest of the plunger.
    Crest,
    /// `u = u_c + w_e`: the protrusion meets the ball.
    EntryRamp,
    /// `u = u_c − w_h`: the ball is fully out on the hold side.
    HoldRampEnd,
    /// `g = g_r`: the magnet's reach.
    MagnetReach,
    /// `u = u_s`: the switch opens or closes.
    Switch,
}

/// Where the ball is: the plunger law's segment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlungerSegment {
    /// The ball is out and does not touch the protrusion.
    Clear,
    /// On the entry ramp (`u_c < u ≤ u_c + w_e`): the ball resists.
    Entry,
    /// On the hold ramp (`u_c − w_h ≤ u ≤ u_c`): the ball pushes in.
    Hold,
}

/// The contact force of the stop, split for bookkeeping.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StopForce<T> {
    /// `k δ^1.5` \[N\]: the elastic part.
    pub elastic_n: T,
    /// `k δ^1.5 + c δ^0.25 δ̇` \[N\], not clamped: negative when the stop
    /// would pull.
    pub raw_n: T,
}

impl<T: Real> StopForce<T> {
    /// The force applied, `max(raw, 0)` \[N\].
    pub(crate) fn applied_n(&self) -> T {
        self.raw_n.max(T::ZERO)
    }
}

fn tan<T: Real>(a: T) -> T {
    let (s, c) = a.sin_cos();
    s / c
}

impl<T: Real> PhysicalLatch<T> {
    /// Checks every parameter: finite, radii and the magnet's decay > 0,
    /// forces, rates, the stroke, the crest, the reach and the switch
    /// travel ≥ 0, ramp angles in (0°, 90°).
    pub fn check(&self) -> Result<(), LatchError> {
        if !(self.side == T::ONE || self.side == -T::ONE) {
            return Err(LatchError::Side);
        }
        let (st, p, m) = (&self.stop, &self.plunger, &self.magnet);
        let non_negative = [
            (st.stiffness_n_per_mm1_5, LatchParam::StopStiffness),
            (st.damping_ns_per_mm1_25, LatchParam::StopDamping),
            (p.preload_n, LatchParam::PlungerPreload),
            (p.stiffness_n_per_mm, LatchParam::PlungerStiffness),
            (p.stroke_mm, LatchParam::PlungerStroke),
            (p.crest_rad, LatchParam::PlungerCrest),
            (m.force_n, LatchParam::MagnetForce),
            (m.reach_mm, LatchParam::MagnetReach),
            (self.switch_travel_rad, LatchParam::SwitchTravel),
        ];
        for (x, name) in non_negative {
            if !(x >= T::ZERO && x.is_finite()) {
                return Err(LatchError::Negative(name));
            }
        }
        let positive = [
            (st.radius_m, LatchParam::StopRadius),
            (p.radius_m, LatchParam::PlungerRadius),
            (m.radius_m, LatchParam::MagnetRadius),
            (m.decay_mm, LatchParam::MagnetDecay),
        ];
        for (x, name) in positive {
            if !(x > T::ZERO && x.is_finite()) {
                return Err(LatchError::NotPositive(name));
            }
        }
        let right = T::PI * T::of(0.5);
        if let Lock::Pawl(pawl) = &self.lock {
            let b = pawl.breaking_torque_nm;
            if !(b > T::ZERO && b.is_finite()) {
                return Err(LatchError::NotPositive(LatchParam::PawlBreakingTorque));
            }
        }
        for (a, name) in [
            (p.entry_ramp_rad, LatchParam::EntryRamp),
            (p.hold_ramp_rad, LatchParam::HoldRamp),
        ] {
            if !(a > T::ZERO && a < right) {
                return Err(LatchError::Ramp(name));
            }
        }
        Ok(())
    }

    /// The travel from the stop `u = s φ` \[rad\].
    #[inline]
    pub fn travel(&self, phi: T) -> T {
        self.side * phi
    }

    /// True while the switch is closed: `u ≤ u_s`.
    pub fn switch_closed(&self, phi: T) -> bool {
        self.travel(phi) <= self.switch_travel_rad
    }

    /// `r_p tan α` [mm/rad] of a ramp: depression per radian of travel.
    fn ramp_rate(&self, angle: T) -> T {
        self.plunger.radius_m * T::of(MM_PER_M) * tan(angle)
    }

    /// `w_e`: angular width of the entry ramp \[rad\].
    pub fn entry_width_rad(&self) -> T {
        self.plunger.stroke_mm / self.ramp_rate(self.plunger.entry_ramp_rad)
    }

    /// `w_h`: angular width of the hold ramp \[rad\].
    pub(crate) fn hold_width_rad(&self) -> T {
        self.plunger.stroke_mm / self.ramp_rate(self.plunger.hold_ramp_rad)
    }

    /// The travel of each [`LatchMark`] \[rad\].
    pub fn marks(&self) -> [(LatchMark, T); 6] {
        let c = self.plunger.crest_rad;
        let reach = self.magnet.reach_mm / (self.magnet.radius_m * T::of(MM_PER_M));
        [
            (LatchMark::Stop, T::ZERO),
            (LatchMark::Crest, c),
            (LatchMark::EntryRamp, c + self.entry_width_rad()),
            (LatchMark::HoldRampEnd, c - self.hold_width_rad()),
            (LatchMark::MagnetReach, reach),
            (LatchMark::Switch, self.switch_travel_rad),
        ]
    }

    /// The plunger's segment at travel `u` \[rad\] (a pawl's cam has no
    /// hold ramp: the pawl drops off the crest into its notch).
    pub fn plunger_segment(&self, u: T) -> PlungerSegment {
        let c = self.plunger.crest_rad;
        if u > c && u <= c + self.entry_width_rad() {
            PlungerSegment::Entry
        } else if u <= c && u >= c - self.hold_width_rad() && matches!(self.lock, Lock::Detent) {
            PlungerSegment::Hold
        } else {
            PlungerSegment::Clear
        }
    }

    /// The ball's depression `x` \[mm\] and `dx/du` [mm/rad] on a segment,
    /// its formula extended beyond the segment's bounds.
    pub(crate) fn depression_on(&self, seg: PlungerSegment, u: T) -> (T, T) {
        self.depression_rated(seg, u, self.ramp_rate_on(seg))
    }

    /// The ramp rate `r = r_p tan α` [mm/rad] of segment `seg` (the entry
    /// or the hold ramp's; zero when clear): a constant of the latch, which
    /// the simulator computes once per segment instead of at every
    /// evaluation ([`Self::conservative_torque_rated`]).
    pub fn ramp_rate_on(&self, seg: PlungerSegment) -> T {
        match seg {
            PlungerSegment::Clear => T::ZERO,
            PlungerSegment::Entry => self.ramp_rate(self.plunger.entry_ramp_rad),
            PlungerSegment::Hold => self.ramp_rate(self.plunger.hold_ramp_rad),
        }
    }

    /// [`Self::depression_on`] with the segment's ramp rate `r` given
    /// ([`Self::ramp_rate_on`]): the same operations, so the same bits.
    fn depression_rated(&self, seg: PlungerSegment, u: T, r: T) -> (T, T) {
        let c = self.plunger.crest_rad;
        match seg {
            PlungerSegment::Clear => (T::ZERO, T::ZERO),
            // w_e = stroke / r_e, as `entry_width_rad`.
            PlungerSegment::Entry => ((c + self.plunger.stroke_mm / r - u) * r, -r),
            // w_h = stroke / r_h, as `hold_width_rad`.
            PlungerSegment::Hold => ((u - c + self.plunger.stroke_mm / r) * r, r),
        }
    }

    /// The plunger's energy `P0 x + ½ k_p x²` \[J\] at depression `x` \[mm\].
    pub(crate) fn plunger_energy_at(&self, x: T) -> T {
        let p = &self.plunger;
        (p.preload_n * x + T::of(0.5) * p.stiffness_n_per_mm * x * x) / T::of(MM_PER_M)
    }

    /// The plunger's torque `τ_u = −dV_p/du` [N·m] on a segment (see
    /// [`Self::plunger_segment`]), its formula extended beyond the bounds.
    pub fn plunger_torque_on(&self, seg: PlungerSegment, u: T) -> T {
        self.plunger_torque_rated(seg, u, self.ramp_rate_on(seg))
    }

    /// [`Self::plunger_torque_on`] with the segment's ramp rate `r`
    /// [mm/rad] given ([`Self::ramp_rate_on`]).
    fn plunger_torque_rated(&self, seg: PlungerSegment, u: T, r: T) -> T {
        let (x, dx) = self.depression_rated(seg, u, r);
        let p = &self.plunger;
        -(p.preload_n + p.stiffness_n_per_mm * x) * dx / T::of(MM_PER_M)
    }

    /// The magnet's force \[N\] at travel `u`, on the segment inside
    /// (`within`) or beyond its reach.
    pub(crate) fn magnet_force_on(&self, within: bool, u: T) -> T {
        let m = &self.magnet;
        if !within || m.force_n == T::ZERO {
            return T::ZERO;
        }
        let g = (u * m.radius_m * T::of(MM_PER_M)).max(T::ZERO);
        let a = self.magnet_floor_term();
        let b = (T::ONE + g / m.decay_mm).max(T::of(MAGNET_FLOOR));
        m.force_n * (T::ONE / (b * b) - a) / (T::ONE - a)
    }

    /// `a = (1 + g_r/g0)^−2`.
    fn magnet_floor_term(&self) -> T {
        let b = T::ONE + self.magnet.reach_mm / self.magnet.decay_mm;
        T::ONE / (b * b)
    }

    /// True while the travel is inside the magnet's reach.
    pub fn magnet_within(&self, u: T) -> bool {
        u * self.magnet.radius_m * T::of(MM_PER_M) < self.magnet.reach_mm
    }

    /// The magnet's potential energy \[J\] at travel `u` (0 beyond the
    /// reach, negative inside it).
    pub fn magnet_energy(&self, u: T) -> T {
        let m = &self.magnet;
        let g = u * m.radius_m * T::of(MM_PER_M);
        if !self.magnet_within(u) || m.force_n == T::ZERO {
            return T::ZERO;
        }
        let a = self.magnet_floor_term();
        let gp = g.max(T::ZERO);
        let inv = |s: T| m.decay_mm / (T::ONE + s / m.decay_mm);
        let w = inv(gp) - inv(m.reach_mm) - a * (m.reach_mm - gp);
        let inside = m.force_n * (g - gp); // g < 0: the force held at F_m0
        (-m.force_n * w / (T::ONE - a) + inside) / T::of(MM_PER_M)
    }

    /// The stop's force at `(φ, φ̇)` (zero while `u ≥ 0`).
    pub fn stop_force(&self, phi: T, phi_dot: T) -> StopForce<T> {
        let r_mm = self.stop.radius_m * T::of(MM_PER_M);
        let delta = -self.travel(phi) * r_mm;
        let delta_dot = -self.travel(phi_dot) * r_mm;
        self.stop.force(delta, delta_dot)
    }

    /// The joint torque `τ_φ` [N·m] of a stop force `force_n` \[N\].
    pub fn stop_torque(&self, force_n: T) -> T {
        self.side * force_n * self.stop.radius_m
    }

    /// The stop's elastic energy `k δ^2.5 / 2.5` \[J\] at `φ`.
    pub fn stop_energy(&self, phi: T) -> T {
        self.stop
            .energy(-self.travel(phi) * self.stop.radius_m * T::of(MM_PER_M))
    }

    /// The conservative joint torque `τ_φ` [N·m] of plunger and magnet at
    /// `φ`, each on the segment its travel is in.
    pub(crate) fn conservative_torque(&self, phi: T) -> T {
        let u = self.travel(phi);
        let seg = self.plunger_segment(u);
        let within = self.magnet_within(u);
        self.side * self.conservative_torque_u(seg, within, u)
    }

    /// `τ_u` [N·m] of plunger and magnet on given segments.
    pub(crate) fn conservative_torque_u(&self, seg: PlungerSegment, within: bool, u: T) -> T {
        self.conservative_torque_rated(seg, within, u, self.ramp_rate_on(seg))
    }

    /// [`Self::conservative_torque_u`] with the plunger segment's ramp rate
    /// `r` [mm/rad] given ([`Self::ramp_rate_on`], computed once): the same
    /// operations, so the same bits, without a tangent per evaluation.
    pub fn conservative_torque_rated(&self, seg: PlungerSegment, within: bool, u: T, r: T) -> T {
        let magnet = self.magnet_force_on(within, u) * self.magnet.radius_m;
        self.plunger_torque_rated(seg, u, r) - magnet
    }

    /// The latch's whole joint torque `τ_φ(φ, φ̇)` [N·m]: stop (clamped at
    /// zero force), plunger and magnet.
    pub fn torque(&self, phi: T, phi_dot: T) -> T {
        let f = self.stop_force(phi, phi_dot).applied_n();
        self.conservative_torque(phi) + self.stop_torque(f)
    }

    /// Potential energy of the conservative parts at `φ` \[J\]: plunger,
    /// magnet and the stop's elastic energy.
    pub fn potential_energy(&self, phi: T) -> T {
        let u = self.travel(phi);
        let (x, _) = self.depression_on(self.plunger_segment(u), u);
        self.plunger_energy_at(x) + self.magnet_energy(u) + self.stop_energy(phi)
    }

    /// Energy to climb the entry ramp to the crest, `P0 h + ½ k_p h²` \[J\]:
    /// the latch's engagement, a resistance of the stroke's last part.
    pub fn engagement_energy(&self) -> T {
        self.plunger_energy_at(self.plunger.stroke_mm)
    }

    /// Energy to take the joint from rest at the stop back over the crest
    /// against plunger and magnet alone \[J\] (the hinge spring not counted).
    pub fn escape_energy(&self) -> T {
        let crest = self.plunger.crest_rad;
        let at_crest = self.plunger_energy_at(self.plunger.stroke_mm) + self.magnet_energy(crest);
        let at_stop = self.potential_energy(T::ZERO);
        at_crest - at_stop
    }

    /// The largest torque the hold ramp opposes to a return,
    /// `(P0 + k_p h) r_p tan α_h` [N·m] (at the crest); a pawl's is its
    /// breaking torque.
    pub fn holding_torque(&self) -> T {
        if let Lock::Pawl(pawl) = &self.lock {
            return pawl.breaking_torque_nm;
        }
        let p = &self.plunger;
        (p.preload_n + p.stiffness_n_per_mm * p.stroke_mm) * self.ramp_rate(p.hold_ramp_rad)
            / T::of(MM_PER_M)
    }

    /// The largest torque the entry ramp opposes to the approach,
    /// `(P0 + k_p h) r_p tan α_e` [N·m] (at the crest): a drive weaker than
    /// this near the crest stops the joint on the ramp.
    pub fn entry_torque(&self) -> T {
        let p = &self.plunger;
        (p.preload_n + p.stiffness_n_per_mm * p.stroke_mm) * self.ramp_rate(p.entry_ramp_rad)
            / T::of(MM_PER_M)
    }
}

#[cfg(test)]
mod tests;
