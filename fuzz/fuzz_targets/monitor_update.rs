//! `Monitor::update` on an arbitrary stream of samples (docs/robustness.md):
//! the monitor of the seed001 T01 mechanism (3 joints), fed samples decoded
//! from the fuzzer's bytes.
//!
//! Each sample takes 8 bytes: `ctrl`, `dt`, then three `i16` (little
//! endian), one per joint.
//! - `ctrl` bits 0–2: the latch switches of joints 1–3.
//! - `ctrl` bit 3: joint `(ctrl >> 4) & 3` (if < 3) reads `NaN` (missing).
//! - `ctrl` bit 6: a bad time stamp chosen by `dt % 6`: NaN, +inf, −inf,
//!   the same time again, 0.2 s back, or a 5 s gap; otherwise the time
//!   advances by `(dt + 1)` ms.
//! - `ctrl` bit 7: the `i16` are absolute angles, `code · 720/32768` deg;
//!   otherwise each moves its joint's last angle by `code · 0.005` deg, so
//!   that small codes make a smooth motion from the stowed angles.
//!
//! Oracle (the monitor's contract, `core/src/faults.rs` and
//! docs/robustness.md): never a panic; no NaN in the status; the
//! confidence in [0, 1]; a confirmed latch is lost only as `escaped` with
//! `latch_disagree` (its inputs say out); every status fits the documented
//! maximum telemetry frame.
#![no_main]

use deploywatch_core::monitor::LatchState;
use deploywatch_core::monitor::{Monitor, Sample, Status};
use deploywatch_core::telemetry::{self, status_frame_max};
use deploywatch_core::monitor::Fault;
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::monitor_config::monitor_config;
use libfuzzer_sys::fuzz_target;
use std::sync::OnceLock;

const N: usize = 3;
const MECHANISM: &str = include_str!("../../data/mechanisms/seed001_T01.toml");

fn template() -> &'static (Monitor<N>, [f32; N]) {
    static T: OnceLock<(Monitor<N>, [f32; N])> = OnceLock::new();
    T.get_or_init(|| {
        let mech =
            Mechanism::from_toml_str(MECHANISM, "seed001_T01.toml").expect("bundled mechanism");
        let cfg = monitor_config::<N>(&mech).expect("monitor configuration");
        let stowed = std::array::from_fn(|j| cfg.joints[j].stowed_deg);
        (Monitor::new(&cfg).expect("monitor"), stowed)
    })
}

fuzz_target!(|data: &[u8]| {
    let (template, stowed) = template();
    let mut monitor = template.clone();
    let mut t = 0.0f32;
    let mut phi = *stowed;
    let mut latched = [false; N];
    let mut frame = [0u8; status_frame_max(N)];
    for rec in data.chunks_exact(8) {
        let (ctrl, dt) = (rec[0], rec[1]);
        let code = |j: usize| i16::from_le_bytes([rec[2 + 2 * j], rec[3 + 2 * j]]);
        let t_s = if ctrl & 0x40 != 0 {
            match dt % 6 {
                0 => f32::NAN,
                1 => f32::INFINITY,
                2 => f32::NEG_INFINITY,
                3 => t,
                4 => t - 0.2,
                _ => {
                    t += 5.0;
                    t
                }
            }
        } else {
            t += f32::from(dt) * 1e-3 + 1e-3;
            t
        };
        for (j, p) in phi.iter_mut().enumerate() {
            *p = if ctrl & 0x80 != 0 {
                f32::from(code(j)) * (720.0 / 32768.0)
            } else {
                (*p + f32::from(code(j)) * 0.005).clamp(-720.0, 720.0)
            };
        }
        let mut reading = phi;
        let missing = usize::from((ctrl >> 4) & 3);
        if ctrl & 0x08 != 0 && missing < N {
            reading[missing] = f32::NAN;
        }
        let sample = Sample::new(t_s, reading, std::array::from_fn(|j| ctrl & (1 << j) != 0));
        let status = monitor.replay_step(&sample);
        check(&status, &mut latched);
        telemetry::encode(&status, &mut frame).expect("a status fits status_frame_max");
    }
});

fn check(status: &Status<N>, latched: &mut [bool; N]) {
    assert!(!status.t_s.is_nan(), "status time is NaN");
    for (j, js) in status.joints.iter().enumerate() {
        let values = [
            ("phi_deg", js.phi_deg),
            ("rate_deg_s", js.rate_deg_s),
            ("coulomb_nm", js.coulomb_nm),
            ("coulomb_sd_nm", js.coulomb_sd_nm),
            ("viscous_nms", js.viscous_nms),
            ("viscous_sd_nms", js.viscous_sd_nms),
            ("friction_torque_nm", js.friction_torque_nm),
            ("confidence", js.confidence),
            ("margin_pct", js.margin_pct.unwrap_or(0.0)),
            ("time_to_latch_s", js.time_to_latch_s.unwrap_or(0.0)),
        ];
        for (name, v) in values {
            assert!(!v.is_nan(), "joint {}: {name} is NaN: {js:?}", j + 1);
        }
        assert!(
            (0.0..=1.0).contains(&js.confidence),
            "joint {}: confidence {}",
            j + 1,
            js.confidence
        );
        // A confirmed latch is lost only when the monitor's own inputs say
        // out (switch open, angle beyond the latch): then the status names
        // the disagreement.
        if latched[j] && js.latch != LatchState::Latched {
            assert!(
                js.latch == LatchState::Escaped && js.faults.contains(Fault::LatchDisagree),
                "joint {}: a confirmed latch was lost without its inputs saying out: {js:?}",
                j + 1
            );
        }
        latched[j] = js.latch == LatchState::Latched;
    }
}
