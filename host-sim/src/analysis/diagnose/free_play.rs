//! An encoder off its panel by the hinge's free-play (`docs/diagnosis.md`,
//! "Free-play held to one side").
//!
//! A hinge with free-play between its spring side and its panel, whose
//! encoder reads the spring side, reads the panel's angle plus the play on
//! one side for as long as the band stays closed on that side: while the
//! spring drives the panel (and after the latching, where it goes on
//! pushing) the spring side sits at the front of the band, leading the
//! panel toward the latch; while the panel is driven back against its
//! spring it trails. A deployment that keeps one of these shows an
//! `encoder_offset` of the play's size; no sensor of such a run tells the
//! two apart.
//!
//! When a joint's mechanisms declare a free-play (`free_play_deg`,
//! `docs/spec/formats.md`, this project's extension), an `encoder_offset`
//! the search kept at that joint whose 95 % interval meets the declared
//! band `[−play, play]` is reported as that discrepancy, named by its
//! signature, and not claimed: it leaves `effects`, and the angles are
//! compared with it taken out ([`apply`]), as the fit compared them.

use super::outcome::{FittedEffect, FreePlayOffset, Outcome};
use crate::data::campaign::Campaign;
use crate::model::effect::EffectKind;

/// The free-play every run's mechanism declares at `joint` (1-based), the
/// least of them \[deg\]; 0 when one declares none.
pub fn declared_play_deg(campaign: &Campaign, joint: usize) -> f64 {
    let mut plays = campaign.runs.iter().map(|r| {
        r.mechanism
            .joints
            .get(joint.wrapping_sub(1))
            .map_or(0.0, |j| j.free_play_deg)
    });
    let first = plays.next().unwrap_or(0.0);
    plays.fold(first, f64::min).max(0.0)
}

/// The offset `m` shows when it is an `encoder_offset` within the declared
/// free-play at its joint: its 95 % interval meets `[−play, play]`.
fn offset_within_play(campaign: &Campaign, m: &FittedEffect) -> Option<FreePlayOffset> {
    if m.candidate.kind != EffectKind::EncoderOffset || m.candidate.table.is_some() {
        return None;
    }
    let joint = m.candidate.joint?;
    let play_deg = declared_play_deg(campaign, joint);
    let offset_deg = *m.params.first()?;
    let ([lo, hi], _) = m.value_ci();
    let within = lo <= play_deg && hi >= -play_deg;
    (play_deg > 0.0 && within && offset_deg.is_finite()).then_some(FreePlayOffset {
        joint,
        offset_deg,
        ci95_deg: [lo, hi],
        play_deg,
    })
}

/// `out` with every `encoder_offset` within its joint's declared free-play
/// moved from the effects found to [`Outcome::free_play`] (its strength
/// with it). The fit's statistics stay: the offset is taken out of the
/// angles instead ([`apply`]), which compares them alike.
pub fn split(campaign: &Campaign, mut out: Outcome) -> Outcome {
    let mut k = 0;
    while k < out.extended.members.len() {
        match offset_within_play(campaign, &out.extended.members[k]) {
            Some(found) => {
                out.extended.members.remove(k);
                if k < out.strength_rms_deg.len() {
                    out.strength_rms_deg.remove(k);
                }
                out.free_play.push(found);
            }
            None => k += 1,
        }
    }
    out
}

/// The campaign with each offset taken out of its joint's angles: the angles
/// as the fit compared them with the effects left.
pub fn apply(campaign: &Campaign, offsets: &[FreePlayOffset]) -> Campaign {
    let mut out = campaign.clone();
    for found in offsets {
        for cr in &mut out.runs {
            if let Some(col) = cr.run.phi_deg.get_mut(found.joint.wrapping_sub(1)) {
                for x in col.iter_mut() {
                    *x -= found.offset_deg;
                }
            }
        }
    }
    out
}

/// The offset in words, for the progress, the summary and the report.
pub fn words(l: &FreePlayOffset) -> String {
    format!(
        "joint {}'s encoder reads {:+.4} deg ({:+.4} .. {:+.4}) off its panel, within the hinge's declared free-play of {:.4} deg: a spring side held at one end of its band reads so, and the runs cannot tell it from an encoder offset; not claimed, taken out of the angles compared",
        l.joint, l.offset_deg, l.ci95_deg[0], l.ci95_deg[1], l.play_deg
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::diagnose::candidate::Candidate;

    fn offset(joint: usize, value: f64, ci: [f64; 2]) -> FittedEffect {
        FittedEffect {
            candidate: Candidate {
                kind: EffectKind::EncoderOffset,
                joint: Some(joint),
                table: None,
            },
            params: vec![value],
            ci95: Some(vec![ci]),
            ci95_search: Some(vec![ci]),
        }
    }

    fn campaign(stowed_deg: f64, play_deg: f64) -> Campaign {
        let text = format!(
            "name = \"m\"\n[[panel]]\nlength_m = 1.0\nmass_kg = 1.0\ncom_m = 0.5\ninertia_kgm2 = 0.1\n[[joint]]\nstowed_deg = {stowed_deg}\nfree_play_deg = {play_deg}\nspring = {{ kind = \"linear\", preload_nm = 1.0, stiffness_nm_per_rad = 0.5, count = 1 }}\n"
        );
        let mechanism =
            crate::model::mechanism::Mechanism::from_toml_str(&text, "m.toml").expect("mechanism");
        let run = crate::data::run::Run {
            t_s: vec![0.0, 0.01],
            phi_deg: vec![vec![stowed_deg, stowed_deg]],
            latch: vec![vec![false, false]],
            ..Default::default()
        };
        Campaign {
            runs: vec![crate::data::campaign::CampaignRun {
                source: "r.csv".into(),
                run,
                mechanism,
                label: None,
            }],
            notes: Vec::new(),
        }
    }

    #[test]
    fn an_offset_within_the_play_is_the_play() {
        let c = campaign(105.0, 0.2);
        assert!(offset_within_play(&c, &offset(1, 0.16, [0.15, 0.20])).is_some());
        assert!(offset_within_play(&c, &offset(1, -0.16, [-0.20, -0.15])).is_some());
        // Beyond the play, but its interval reaches into it.
        assert!(offset_within_play(&c, &offset(1, 0.25, [0.13, 0.31])).is_some());
        assert!(offset_within_play(&c, &offset(1, -0.25, [-0.31, -0.19])).is_some());
    }

    #[test]
    fn an_offset_the_play_cannot_give_stays_a_claim() {
        let c = campaign(105.0, 0.2);
        // Clearly beyond the play, either way.
        assert!(offset_within_play(&c, &offset(1, 0.5, [0.45, 0.55])).is_none());
        assert!(offset_within_play(&c, &offset(1, -0.5, [-0.55, -0.45])).is_none());
        // No play declared.
        let c = campaign(105.0, 0.0);
        assert!(offset_within_play(&c, &offset(1, 0.16, [0.15, 0.20])).is_none());
    }

    #[test]
    fn apply_takes_the_offset_out_of_its_joint() {
        let c = campaign(105.0, 0.2);
        let found =
            offset_within_play(&c, &offset(1, 0.16, [0.15, 0.20])).expect("within the play");
        let a = apply(&c, &[found]);
        assert!((a.runs[0].run.phi_deg[0][0] - (105.0 - 0.16)).abs() < 1e-12);
    }
}
