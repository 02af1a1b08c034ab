//! The simulator's bundled physical-latch runs through the monitor
//! configured from their mechanism files.

use super::*;

/// The simulator's bundled physical-latch runs (`data/examples/latch_*`,
/// their truth in each README) through the monitor configured from their
/// mechanism files: the final states the truth gives, every escape seen,
/// never latched while the switch is open. Flags are printed, not asserted
/// (`docs/monitor.md` §4.1 lists them).
#[test]
fn bundled_physical_latch_runs() {
    let cases: [(&str, &str, &[LatchState]); 4] = [
        (
            "latch_clean_bounce",
            "seed001_T02_physical_latch",
            &[
                LatchState::Stalled,
                LatchState::Latched,
                LatchState::Latched,
            ],
        ),
        (
            "latch_escape_never",
            "seed001_T01_physical_latch",
            &[
                LatchState::Latched,
                LatchState::Escaped,
                LatchState::Latched,
            ],
        ),
        (
            "latch_escape_relatch",
            "one_panel_physical_latch",
            &[LatchState::Latched],
        ),
        (
            "latch_ramp_stop",
            "one_panel_physical_latch",
            &[LatchState::StoppedShort],
        ),
    ];
    for (dir, mech_name, finals) in cases {
        let path = std::fs::read_dir(data_dir().join("examples").join(dir))
            .unwrap()
            .map(|e| e.unwrap().path())
            .find(|p| p.extension().is_some_and(|x| x == "csv"))
            .unwrap();
        let run = Run::load(&path).unwrap();
        let mech = mechanism(mech_name);
        match finals.len() {
            1 => check_bundled::<1>(dir, &mech, &run, finals),
            3 => check_bundled::<3>(dir, &mech, &run, finals),
            n => panic!("{n} joints"),
        }
    }
}

fn check_bundled<const N: usize>(dir: &str, mech: &Mechanism, run: &Run, finals: &[LatchState]) {
    let cfg = monitor_config::<N>(mech).expect("monitor config");
    assert!(
        cfg.joints.iter().any(|j| j.physical.is_some()),
        "{dir}: no physical latch configured"
    );
    let st = replay(&cfg, run);
    for (j, want) in finals.iter().enumerate() {
        let last = st.last().unwrap().joints[j].latch;
        let flags: Vec<String> = st
            .iter()
            .filter(|s| !s.joints[j].faults.is_empty())
            .map(|s| format!("{} at {:.2} s", s.joints[j].faults, s.t_s))
            .collect();
        let escapes = st
            .windows(2)
            .filter(|w| {
                w[1].joints[j].latch == LatchState::Escaped
                    && w[0].joints[j].latch != LatchState::Escaped
            })
            .count();
        println!(
            "{dir} joint {}: final {last}, {escapes} escapes reported, flags {flags:?}",
            j + 1
        );
        assert_eq!(last, *want, "{dir} joint {}", j + 1);
        for (i, s) in st.iter().enumerate() {
            assert!(
                s.joints[j].latch != LatchState::Latched || run.latch[j][i],
                "{dir} joint {}: latched at {} s with the switch open",
                j + 1,
                s.t_s
            );
        }
    }
}
