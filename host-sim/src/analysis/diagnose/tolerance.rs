//! The drawing's declared tolerances of mass, inertia and spring torque in
//! the reported intervals (`docs/diagnosis.md`, "What the drawing's
//! tolerances add").
//!
//! The fit compares the runs with the drawing's wing; the wing as built
//! differs from it within its tolerances (`mass_tolerance_pct`,
//! `inertia_tolerance_pct` of a `[[panel]]`, `spring_tolerance_pct` of a
//! `[[joint]]`: the spring's torque at every angle; this project's
//! extension). An effect's estimate moves with them, and the fit's own
//! interval, which only knows the noise and what the fit leaves, does not
//! hold that.
//!
//! For each mechanism of the campaign and each property of a panel or a
//! spring with a declared half band `b` \[%\], the set found is fitted
//! again with that property at the band's edge (`× (1 + b/100)`, in every
//! run of that mechanism), from the set's own parameters; `Δ_k` is how far
//! each parameter moves. The property as built is taken uniform within its
//! band (GUM, type B: standard uncertainty `b/√3`), the moves linear in it
//! and independent, so the tolerances give each parameter the standard
//! uncertainty `u = √(Σ_k Δ_k² / 3)`, and each side of its reported 95 %
//! interval is widened to `√(h² + (z₀.₉₇₅ u)²)` (`h`: that side's half
//! width).
//!
//! A named effect whose value the fit's ordinary interval, so widened,
//! does not hold clear of zero (a torque table: its knots together,
//! [`table_clearance`]; a spring softening: clear of its joint's declared
//! spring band, [`within_spring_band`]) is one the tolerances alone could make: it
//! is taken out of the set (the least clear first, the rest refitted, the
//! shares computed again) and reported as such, not claimed ([`settle`]).

use super::candidate::Candidate;
use super::outcome::{FittedEffect, FittedSet, ToleranceShare, WithinTolerance};
use super::Engine;
use crate::analysis::fit::Z_975;
use crate::data::campaign::Campaign;
use crate::model::effect::EffectKind;
use rayon::prelude::*;

/// A declared property of a mechanism, 0-based.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Property {
    /// A panel's mass (`mass_tolerance_pct`).
    Mass(usize),
    /// A panel's inertia (`inertia_tolerance_pct`).
    Inertia(usize),
    /// A joint's spring torque at every angle (`spring_tolerance_pct`).
    Spring(usize),
}

/// One declared property of one mechanism, moved to its band's edge.
#[derive(Clone, Debug, PartialEq)]
struct Edge {
    /// The mechanism's name.
    mechanism: String,
    /// The property.
    property: Property,
    /// The declared half band \[%\].
    pct: f64,
}

impl Edge {
    /// `panel 2's inertia (±1 %) of seed001-T01`, `joint 3's spring (±2 %)
    /// of seed001-T01`.
    fn words(&self) -> String {
        let what = match self.property {
            Property::Mass(i) => format!("panel {}'s mass", i + 1),
            Property::Inertia(i) => format!("panel {}'s inertia", i + 1),
            Property::Spring(j) => format!("joint {}'s spring", j + 1),
        };
        format!("{what} (±{} %) of {}", self.pct, self.mechanism)
    }

    /// `campaign` with this property at its band's edge.
    fn moved(&self, campaign: &Campaign) -> Campaign {
        let mut c = campaign.clone();
        let scale = 1.0 + self.pct / 100.0;
        for r in c
            .runs
            .iter_mut()
            .filter(|r| r.mechanism.name == self.mechanism)
        {
            let m = &mut r.mechanism;
            match self.property {
                Property::Mass(i) => {
                    if let Some(p) = m.panels.get_mut(i) {
                        p.mass_kg *= scale;
                    }
                }
                Property::Inertia(i) => {
                    if let Some(p) = m.panels.get_mut(i) {
                        p.inertia_kgm2 *= scale;
                    }
                }
                Property::Spring(j) => {
                    if let Some(joint) = m.joints.get_mut(j) {
                        joint.spring = joint.spring.scaled(scale);
                    }
                }
            }
        }
        c
    }
}

/// Every declared tolerance of the campaign's mechanisms, each mechanism
/// once: the panels' in order, then the springs'.
fn edges(campaign: &Campaign) -> Vec<Edge> {
    let mut out: Vec<Edge> = Vec::new();
    let mut seen: Vec<&str> = Vec::new();
    for r in &campaign.runs {
        let m = &r.mechanism;
        if seen.contains(&m.name.as_str()) {
            continue;
        }
        seen.push(&m.name);
        let panels = (0..m.panels.len()).flat_map(|i| {
            let tol = m.mass_tolerance(i);
            [
                (Property::Mass(i), tol.mass_pct),
                (Property::Inertia(i), tol.inertia_pct),
            ]
        });
        let springs = m
            .joints
            .iter()
            .enumerate()
            .map(|(j, joint)| (Property::Spring(j), joint.spring_tolerance_pct));
        out.extend(
            panels
                .chain(springs)
                .filter(|&(_, pct)| pct > 0.0)
                .map(|(property, pct)| Edge {
                    mechanism: m.name.clone(),
                    property,
                    pct,
                }),
        );
    }
    out
}

/// Each side of an interval `[lo, hi]` around `p` widened by `add` \[the
/// parameter's unit\], in quadrature.
pub fn widen_side(p: f64, [lo, hi]: [f64; 2], add: f64) -> [f64; 2] {
    let side = |h: f64| (h * h + add * add).sqrt();
    [p - side(p - lo), p + side(hi - p)]
}

/// Each member's share of the tolerances, in the set's order; `None`
/// when no tolerance is declared, the set is empty, the search was
/// halted, or a refit at a band's edge failed.
fn shares(eng: &Engine<'_>, found: &FittedSet) -> Option<Vec<ToleranceShare>> {
    let edges = edges(eng.campaign);
    if edges.is_empty() || found.members.is_empty() || eng.halt.now() {
        return None;
    }
    let p0 = found.params();
    let moves: Vec<Vec<f64>> = edges
        .par_iter()
        .map(|e| {
            let p = eng.refit(&e.moved(eng.campaign), found)?.params();
            Some(p.iter().zip(&p0).map(|(a, b)| a - b).collect())
        })
        .collect::<Option<_>>()?;
    let mut out = Vec::with_capacity(found.members.len());
    let mut off = 0;
    for m in &found.members {
        let n = m.params.len();
        let size = |k: usize| moves[k][off..off + n].iter().map(|x| x * x).sum::<f64>();
        let largest = (0..edges.len())
            .max_by(|&a, &b| size(a).total_cmp(&size(b)))
            .map(|k| edges[k].words())
            .unwrap_or_default();
        out.push(ToleranceShare {
            candidate: m.candidate,
            effect: m.candidate.words(),
            sd: (off..off + n)
                .map(|i| (moves.iter().map(|d| d[i] * d[i]).sum::<f64>() / 3.0).sqrt())
                .collect(),
            largest,
        });
        off += n;
    }
    Some(out)
}

/// The set `found` with each member's reported interval widened by its
/// share ([`widen_side`], `1.96 u` per parameter).
pub(super) fn widen(found: &FittedSet, shares: &[ToleranceShare]) -> FittedSet {
    let mut out = found.clone();
    for m in out.members.iter_mut() {
        let Some(share) = shares.iter().find(|s| s.candidate == m.candidate) else {
            continue;
        };
        if let Some(ci) = m.ci95.as_mut() {
            for ((band, &p), &u) in ci.iter_mut().zip(&m.params).zip(&share.sd) {
                *band = widen_side(p, *band, Z_975 * u);
            }
        }
    }
    out
}

/// The shares in the order of the set's members.
pub(super) fn in_order(found: &FittedSet, shares: &[ToleranceShare]) -> Vec<ToleranceShare> {
    found
        .members
        .iter()
        .filter_map(|m| shares.iter().find(|s| s.candidate == m.candidate).cloned())
        .collect()
}

/// The 0.95 quantile of χ² with `k` degrees of freedom, by the cube-root
/// normal approximation of Wilson & Hilferty (1931),
/// `k (1 − 2/(9k) + z₀.₉₅ √(2/(9k)))³`: within 1 % of the exact value for
/// `k ≥ 2` (5.94 for 2 against 5.99, 11.05 for 5 against 11.07).
fn chi2_95(k: usize) -> f64 {
    /// The standard normal's 0.95 quantile.
    const Z_95: f64 = 1.644_853_626_951_472_2;
    let k = k.max(1) as f64;
    let a = 2.0 / (9.0 * k);
    k * (1.0 - a + Z_95 * a.sqrt()).powi(3)
}

/// How far a torque table's knots stand clear of zero with their
/// intervals `widened`: `√(Σ (p_i/s_i)² / χ²_k(0.95))` (`s_i` half the
/// knot's interval over 1.96, the knots taken independent), above 1 when
/// the table as a whole is clear of zero at 95 %.
fn table_clearance(params: &[f64], widened: &[[f64; 2]]) -> f64 {
    let stat: f64 = params
        .iter()
        .zip(widened)
        .map(|(p, [lo, hi])| {
            let s = 0.5 * (hi - lo) / Z_975;
            if s > 0.0 {
                (p / s).powi(2)
            } else {
                f64::INFINITY
            }
        })
        .sum();
    (stat / chi2_95(params.len())).sqrt()
}

/// The fit's ordinary interval of each of `m`'s parameters, each side
/// widened by `1.96 u` (its share) in quadrature ([`widen_side`]).
fn widened(m: &FittedEffect, share: &ToleranceShare) -> Option<Vec<[f64; 2]>> {
    let ci = m.ci95_search.as_ref()?;
    Some(
        ci.iter()
            .zip(&m.params)
            .zip(&share.sd)
            .map(|((band, &p), &u)| widen_side(p, *band, Z_975 * u))
            .collect(),
    )
}

/// The spring tolerance every run's mechanism declares at joint `joint`
/// (1-based), as a fraction: the least of them; `None` where a run's
/// mechanism declares none there.
fn spring_band(campaign: &Campaign, joint: usize) -> Option<f64> {
    campaign
        .runs
        .iter()
        .map(|r| {
            let pct = r
                .mechanism
                .joints
                .get(joint.checked_sub(1)?)?
                .spring_tolerance_pct;
            (pct > 0.0).then_some(pct / 100.0)
        })
        .try_fold(f64::INFINITY, |least, b| Some(least.min(b?)))
        .filter(|b| b.is_finite())
}

/// A spring softening `s` at a joint whose drawing declares its spring's
/// torque within `±b` is that spring built at `1 − s` of its drawing
/// (physics.md: the softening scales the spring's torque by `1 − s`): where
/// its interval, widened by its share, meets `[−b, b]`, the wing as built
/// within its drawing makes it exactly. How far its value stands beyond
/// the band, over the band (`Some`, ≤ 1 inside it); `None` clear of it.
fn within_spring_band(m: &FittedEffect, widened: &[[f64; 2]], band: f64) -> Option<f64> {
    let ([lo, hi], _) = m.candidate.value_ci(&m.params, widened);
    let value = m.params.first()?.abs();
    (lo <= band && hi >= -band).then_some(value / band)
}

/// The share a spring softening at a joint with a declared spring band
/// `±b` takes from it when the band itself holds it ([`within_spring_band`],
/// on its fit's interval): the band moves a softening by exactly `±b`, so
/// that the report's "the tolerances alone move it by ±b at 95 %" is what
/// sets it apart. `None` for any other effect.
fn band_share(
    campaign: &Campaign,
    m: &FittedEffect,
    share: &ToleranceShare,
) -> Option<ToleranceShare> {
    let joint = m.candidate.joint?;
    let band = spring_band(campaign, joint)?;
    if m.candidate.kind != EffectKind::SpringSoftening
        || within_spring_band(m, &widened(m, share)?, band).is_none()
    {
        return None;
    }
    Some(ToleranceShare {
        candidate: m.candidate,
        effect: m.candidate.words(),
        sd: vec![band / Z_975],
        largest: format!(
            "joint {joint}'s spring (±{} %), whose torque a softening scales",
            100.0 * band
        ),
    })
}

/// How far a named effect stands clear of what the tolerances alone could
/// make of it, with the fit's ordinary interval widened by `1.96 u` per
/// parameter: its value over its 95 % half band
/// ([`FittedEffect::clear_of_zero`]'s test on it), a spring softening's
/// value against its joint's declared spring band (`spring_band`,
/// [`within_spring_band`]), or a torque table's knots together
/// ([`table_clearance`]); `None` for an effect clear of it.
fn within_share(m: &FittedEffect, share: &ToleranceShare, spring_band: Option<f64>) -> Option<f64> {
    let widened = widened(m, share)?;
    if m.candidate.table.is_some() {
        let clearance = table_clearance(&m.params, &widened);
        return (clearance <= 1.0).then_some(clearance);
    }
    if let (EffectKind::SpringSoftening, Some(band)) = (m.candidate.kind, spring_band) {
        if let Some(c) = within_spring_band(m, &widened, band) {
            return Some(c);
        }
    }
    let probe = FittedEffect {
        ci95_search: Some(widened),
        ..m.clone()
    };
    if probe.clear_of_zero() {
        return None;
    }
    let [lo, hi] = probe.search_value_ci();
    let value = 0.5 * (lo + hi);
    Some(value.abs() / (0.5 * (hi - lo)).max(f64::MIN_POSITIVE))
}

/// The set found once every named effect the drawing's tolerances alone
/// could make is taken out, and the shares of what is left.
pub(super) struct Settled {
    /// The set, refitted without them.
    pub set: FittedSet,
    /// Its members' shares (empty: no tolerance declared, or not computed).
    pub shares: Vec<ToleranceShare>,
    /// The effects taken out, in the order they were.
    pub within: Vec<WithinTolerance>,
}

/// `set` without its member `k`, refitted; for a Stribeck friction, with
/// Coulomb friction at its kinetic level in its place, refitted, and that
/// Coulomb friction: what the tolerances could make is the break-away's
/// excess over the kinetic level (a Stribeck law holds Coulomb friction,
/// `ΔT = 0`), not the friction. Another single law in its place would be
/// another explanation, not the same one reduced: the sets alike formed
/// again around the set settled list it ([`super::ambiguity`]).
fn in_its_place(
    eng: &Engine<'_>,
    set: &FittedSet,
    k: usize,
) -> Option<(FittedSet, Option<Candidate>)> {
    let without = set.without(k);
    match set.members.get(k) {
        Some(m) if m.candidate.kind == EffectKind::StribeckFriction => {
            let coulomb = Candidate {
                kind: EffectKind::CoulombFriction,
                joint: m.candidate.joint,
                table: None,
            };
            if without.candidates().contains(&coulomb) {
                return eng.refit(eng.campaign, &without).map(|f| (f, None));
            }
            let kinetic = m.params.first().copied().unwrap_or(0.0);
            let start = without.with(FittedEffect::start(coulomb, vec![kinetic]));
            eng.refit(eng.campaign, &start).map(|f| (f, Some(coulomb)))
        }
        _ => eng.refit(eng.campaign, &without).map(|f| (f, None)),
    }
}

/// Takes out of `found`, one at a time (the least clear first, the rest
/// refitted), each named effect whose value the fit's interval widened by
/// its share of the tolerances does not hold clear of zero: the runs
/// cannot tell it from a wing built within its drawing's tolerances (a
/// Stribeck friction gives way to Coulomb friction at its kinetic level,
/// [`in_its_place`]).
pub(super) fn settle(eng: &Engine<'_>, found: FittedSet) -> Settled {
    let mut set = found;
    let mut within = Vec::new();
    loop {
        let Some(shares) = shares(eng, &set) else {
            return Settled {
                set,
                shares: Vec::new(),
                within,
            };
        };
        let weakest = set
            .members
            .iter()
            .enumerate()
            .filter_map(|(k, m)| {
                let band = m.candidate.joint.and_then(|j| spring_band(eng.campaign, j));
                Some((k, within_share(m, shares.get(k)?, band)?))
            })
            .min_by(|a, b| a.1.total_cmp(&b.1));
        let Some((k, _)) = weakest else {
            return Settled {
                set,
                shares,
                within,
            };
        };
        let Some((refit, placed)) = in_its_place(eng, &set, k) else {
            return Settled {
                set,
                shares,
                within,
            };
        };
        let taken = WithinTolerance {
            effect: set.members[k].clone(),
            in_its_place: placed,
            share: band_share(eng.campaign, &set.members[k], &shares[k])
                .unwrap_or_else(|| shares[k].clone()),
        };
        eng.say(format!(
            "  set apart {}{}: the drawing's declared tolerances of mass, inertia and spring torque alone could make it (±{} at 95 %, most from {})",
            taken.effect.candidate.words(),
            placed.map_or_else(String::new, |c| format!(" ({} in its place)", c.words())),
            taken
                .share
                .sd
                .iter()
                .map(|u| format!("{:.4}", Z_975 * u))
                .collect::<Vec<_>>()
                .join(", "),
            taken.share.largest
        ));
        within.push(taken);
        set = refit;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The candidate of a spring softening at joint 1.
    fn at_joint_1() -> crate::analysis::diagnose::Candidate {
        crate::analysis::diagnose::Candidate {
            kind: EffectKind::SpringSoftening,
            joint: Some(1),
            table: None,
        }
    }

    /// A spring softening at joint 1 of value `s` with the interval `ci`.
    fn softening(s: f64, ci: [f64; 2]) -> FittedEffect {
        FittedEffect {
            ci95_search: Some(vec![ci]),
            ..FittedEffect::start(at_joint_1(), vec![s])
        }
    }

    #[test]
    fn a_softening_within_the_declared_spring_band_is_the_spring_as_built() {
        let share = ToleranceShare {
            candidate: at_joint_1(),
            effect: String::new(),
            sd: vec![0.001],
            largest: String::new(),
        };
        // 1.95 % with a narrow interval, clear of zero, within a ±2 % band.
        let m = softening(0.0195, [0.0180, 0.0210]);
        assert!(within_share(&m, &share, None).is_none());
        let c = within_share(&m, &share, Some(0.02)).expect("within the band");
        assert!((c - 0.975).abs() < 1e-9, "{c}");
        // 5 % is beyond it, whatever the band's share.
        let m = softening(0.05, [0.047, 0.053]);
        assert!(within_share(&m, &share, Some(0.02)).is_none());
    }

    #[test]
    fn the_chi2_quantile_is_within_a_per_cent() {
        // Exact values: χ²_k(0.95) for k = 2, 5, 10, 24.
        for (k, exact) in [
            (2, 5.991_465),
            (5, 11.070_50),
            (10, 18.307_04),
            (24, 36.415_03),
        ] {
            let q = chi2_95(k);
            assert!((q / exact - 1.0).abs() < 0.01, "k {k}: {q} against {exact}");
        }
    }

    #[test]
    fn a_table_is_clear_when_its_knots_together_are() {
        // Five knots each 1.3 standard errors off zero: χ² 8.45 < 11.07.
        let s = 1.0;
        let band = |p: f64| [p - Z_975 * s, p + Z_975 * s];
        let p = [1.3; 5];
        let w: Vec<_> = p.iter().map(|&x| band(x)).collect();
        assert!(table_clearance(&p, &w) < 1.0);
        // Each 1.6 off: χ² 12.8 > 11.07.
        let p = [1.6; 5];
        let w: Vec<_> = p.iter().map(|&x| band(x)).collect();
        assert!(table_clearance(&p, &w) > 1.0);
    }

    #[test]
    fn a_side_grows_in_quadrature_and_never_shrinks() {
        let [lo, hi] = widen_side(1.0, [0.7, 1.4], 0.4);
        assert!((1.0 - lo - 0.5).abs() < 1e-12, "{lo}");
        assert!((hi - 1.0 - (0.16f64 + 0.16).sqrt()).abs() < 1e-12, "{hi}");
        assert_eq!(widen_side(2.0, [1.5, 2.5], 0.0), [1.5, 2.5]);
    }

    #[test]
    fn each_mechanism_gives_its_declared_bands_once() {
        let text = std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../data/mechanisms/seed001_T01.toml"
        ))
        .expect("the bundled mechanism");
        let plain =
            crate::model::mechanism::Mechanism::from_toml_str(&text, "t01").expect("it parses");
        let mut declared = plain.clone();
        declared.name = "t01-declared".into();
        declared.mass_tolerances[1].inertia_pct = 1.0;
        declared.mass_tolerances[2].mass_pct = 0.5;
        declared.joints[0].spring_tolerance_pct = 2.0;
        let opts = crate::simulate::trajectory::SimOptions::default();
        let noise = &crate::simulate::sensor::SensorModel::REFERENCE;
        let run = crate::simulate::deployment::simulate(&plain, &[], &opts)
            .map(|t| crate::simulate::sensor::measure(&t, &[0.0; 3], noise, 1))
            .expect("a run");
        let mut c = Campaign::default();
        for (m, name) in [
            (&plain, "a.csv"),
            (&declared, "b.csv"),
            (&declared, "c.csv"),
        ] {
            c.runs.push(crate::data::campaign::CampaignRun {
                source: name.into(),
                run: run.clone(),
                mechanism: m.clone(),
                label: None,
            });
        }
        let e = edges(&c);
        assert_eq!(e.len(), 3, "{e:?}");
        assert_eq!(e[0].words(), "panel 2's inertia (±1 %) of t01-declared");
        assert_eq!(e[2].words(), "joint 1's spring (±2 %) of t01-declared");
        let moved = e[1].moved(&c);
        let mass = |c: &Campaign, r: usize| c.runs[r].mechanism.panels[2].mass_kg;
        assert_eq!(mass(&moved, 0), mass(&c, 0));
        assert_eq!(mass(&moved, 1), mass(&c, 1) * 1.005);
        assert_eq!(mass(&moved, 2), mass(&c, 2) * 1.005);
        let sprung = e[2].moved(&c);
        let spring = |c: &Campaign, r: usize| c.runs[r].mechanism.joints[0].spring.clone();
        assert_eq!(spring(&sprung, 0), spring(&c, 0));
        assert_eq!(spring(&sprung, 1), spring(&c, 1).scaled(1.02));
        assert_ne!(spring(&sprung, 1), spring(&c, 1));
    }
}
