//! The panels' declared mass-property tolerances in the reported intervals
//! (`docs/diagnosis.md`, "What the drawing's tolerances add").
//!
//! The fit compares the runs with the drawing's panels; the panels as built
//! differ from it within their tolerances (`mass_tolerance_pct`,
//! `inertia_tolerance_pct` of a `[[panel]]`, this project's extension). An
//! effect's estimate moves with them, and the fit's own interval, which
//! only knows the noise and what the fit leaves, does not hold that.
//!
//! For each mechanism of the campaign, each panel and each property with a
//! declared half band `b` \[%\], the set found is fitted again with that
//! property at the band's edge (`× (1 + b/100)`, in every run of that
//! mechanism), from the set's own parameters; `Δ_k` is how far each
//! parameter moves. The property as built is taken uniform within its band
//! (GUM, type B: standard uncertainty `b/√3`), the moves linear in it and
//! independent, so the tolerances give each parameter the standard
//! uncertainty `u = √(Σ_k Δ_k² / 3)`, and each side of its reported 95 %
//! interval is widened to `√(h² + (z₀.₉₇₅ u)²)` (`h`: that side's half
//! width).
//!
//! A named effect whose value the fit's ordinary interval, so widened,
//! does not hold clear of zero is one the tolerances alone could make: it
//! is taken out of the set (the least clear first, the rest refitted, the
//! shares computed again) and reported as such, not claimed ([`settle`]).

use super::outcome::{FittedEffect, FittedSet, ToleranceShare, WithinTolerance};
use super::Engine;
use crate::analysis::fit::Z_975;
use crate::data::campaign::Campaign;
use rayon::prelude::*;

/// One property of one panel of one mechanism, moved to its band's edge.
#[derive(Clone, Debug, PartialEq)]
struct Edge {
    /// The mechanism's name.
    mechanism: String,
    /// 0-based panel.
    panel: usize,
    /// True: the inertia; false: the mass.
    inertia: bool,
    /// The declared half band \[%\].
    pct: f64,
}

impl Edge {
    /// `panel 2's inertia (±1 %) of seed001-T01`.
    fn words(&self) -> String {
        format!(
            "panel {}'s {} (±{} %) of {}",
            self.panel + 1,
            if self.inertia { "inertia" } else { "mass" },
            self.pct,
            self.mechanism
        )
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
            if let Some(p) = r.mechanism.panels.get_mut(self.panel) {
                if self.inertia {
                    p.inertia_kgm2 *= scale;
                } else {
                    p.mass_kg *= scale;
                }
            }
        }
        c
    }
}

/// Every declared tolerance of the campaign's mechanisms, each mechanism
/// once.
fn edges(campaign: &Campaign) -> Vec<Edge> {
    let mut out: Vec<Edge> = Vec::new();
    let mut seen: Vec<&str> = Vec::new();
    for r in &campaign.runs {
        let m = &r.mechanism;
        if seen.contains(&m.name.as_str()) {
            continue;
        }
        seen.push(&m.name);
        for panel in 0..m.panels.len() {
            let tol = m.mass_tolerance(panel);
            for (inertia, pct) in [(false, tol.mass_pct), (true, tol.inertia_pct)] {
                if pct > 0.0 {
                    out.push(Edge {
                        mechanism: m.name.clone(),
                        panel,
                        inertia,
                        pct,
                    });
                }
            }
        }
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

/// How far a named effect stands clear of what the tolerances alone could
/// make of it: its value over its 95 % half band with its share, the
/// fit's ordinary interval widened by `1.96 u` per parameter
/// ([`FittedEffect::clear_of_zero`]'s test on it); `None` for a torque
/// table (judged by the discrepancy's rules) and an effect clear of it.
fn within_share(m: &FittedEffect, share: &ToleranceShare) -> Option<f64> {
    if m.candidate.table.is_some() {
        return None;
    }
    let ci = m.ci95_search.as_ref()?;
    let widened: Vec<[f64; 2]> = ci
        .iter()
        .zip(&m.params)
        .zip(&share.sd)
        .map(|((band, &p), &u)| widen_side(p, *band, Z_975 * u))
        .collect();
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

/// The set found once every named effect the panels' tolerances alone
/// could make is taken out, and the shares of what is left.
pub(super) struct Settled {
    /// The set, refitted without them.
    pub set: FittedSet,
    /// Its members' shares (empty: no tolerance declared, or not computed).
    pub shares: Vec<ToleranceShare>,
    /// The effects taken out, in the order they were.
    pub within: Vec<WithinTolerance>,
}

/// Takes out of `found`, one at a time (the least clear first, the rest
/// refitted), each named effect whose value the fit's interval widened by
/// its share of the tolerances does not hold clear of zero: the runs
/// cannot tell it from panels within their drawing's tolerances.
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
            .filter_map(|(k, m)| Some((k, within_share(m, shares.get(k)?)?)))
            .min_by(|a, b| a.1.total_cmp(&b.1));
        let Some((k, _)) = weakest else {
            return Settled {
                set,
                shares,
                within,
            };
        };
        let Some(refit) = eng.refit(eng.campaign, &set.without(k)) else {
            return Settled {
                set,
                shares,
                within,
            };
        };
        let taken = WithinTolerance {
            effect: set.members[k].clone(),
            share: shares[k].clone(),
        };
        eng.say(format!(
            "  set apart {}: the panels' declared mass-property tolerances alone could make it (±{} at 95 %, most from {})",
            taken.effect.candidate.words(),
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
            });
        }
        let e = edges(&c);
        assert_eq!(e.len(), 2, "{e:?}");
        assert_eq!(e[0].words(), "panel 2's inertia (±1 %) of t01-declared");
        let moved = e[1].moved(&c);
        let mass = |c: &Campaign, r: usize| c.runs[r].mechanism.panels[2].mass_kg;
        assert_eq!(mass(&moved, 0), mass(&c, 0));
        assert_eq!(mass(&moved, 1), mass(&c, 1) * 1.005);
        assert_eq!(mass(&moved, 2), mass(&c, 2) * 1.005);
    }
}
