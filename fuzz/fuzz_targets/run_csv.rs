//! The run CSV reader on arbitrary bytes (docs/robustness.md).
//!
//! Oracle: never a panic; a run that is read passes its own checks the way
//! the writer needs them, and writing it, reading that back and writing
//! again gives the same text (the writer's documented round trip).
#![no_main]

use deploywatch_sim::run::{ReadOptions, Run};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    // Run::load_with rejects non-UTF-8 files before parsing.
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    for allow_missing in [false, true] {
        let options = ReadOptions { allow_missing };
        let Ok(run) = Run::parse_with(text, "fuzz.csv", options) else {
            continue;
        };
        assert!(run.joints() >= 1 && run.len() >= 1);
        assert!(run.phi_deg.iter().all(|s| s.len() == run.len()));
        assert!(run.latch.iter().all(|s| s.len() == run.len()));
        assert!(run.t_s.windows(2).all(|w| w[0] < w[1]));
        let _ = run.motion_deg();
        // The writer needs times at least 1 µs apart, which the reader does
        // not ask of a file: only runs that pass `validate` round-trip.
        if run.validate("fuzz.csv").is_err() {
            continue;
        }
        let once = run.to_csv_string();
        let back = Run::parse_with(&once, "once.csv", options)
            .unwrap_or_else(|e| panic!("written run does not read back: {e}\n{once}"));
        assert_eq!(back.to_csv_string(), once, "write-read-write differs");
    }
});
