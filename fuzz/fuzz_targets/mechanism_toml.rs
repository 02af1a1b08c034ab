//! The mechanism TOML reader on arbitrary bytes (docs/robustness.md).
//!
//! Oracle: never a panic; a mechanism that is read writes back as TOML that
//! reads as the same mechanism (the writer's documented round trip), and
//! converts to a monitor configuration or says why not.
#![no_main]

use deploywatch_core::monitor::Monitor;
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::monitor_config::monitor_config;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(mech) = Mechanism::from_toml_str(text, "fuzz.toml") else {
        return;
    };
    let written = mech.to_toml_string();
    let back = Mechanism::from_toml_str(&written, "written.toml")
        .unwrap_or_else(|e| panic!("written mechanism does not read back: {e}\n{written}"));
    assert_eq!(back, mech, "write-read differs:\n{written}");
    // The on-board side: a configuration, then a monitor, or an error.
    match mech.joint_count() {
        1 => monitor::<1>(&mech),
        2 => monitor::<2>(&mech),
        3 => monitor::<3>(&mech),
        4 => monitor::<4>(&mech),
        _ => {}
    }
});

fn monitor<const N: usize>(mech: &Mechanism) {
    if let Ok(cfg) = monitor_config::<N>(mech) {
        let _ = Monitor::new(&cfg);
    }
}
