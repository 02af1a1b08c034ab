//! The words of the diagnosis's typed findings: why a search stopped
//! before its end ([`HaltReason`]). The analysis decides and holds the
//! facts; the report, the JSON and the summary say them with these words.

use crate::analysis::diagnose::HaltReason;
use std::fmt;

/// The words of the JSON's `partial`, the report's bold line and the
/// summary's `PARTIAL:` (they name the command line's `--max-seconds`).
impl fmt::Display for HaltReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            HaltReason::Interrupted => f.write_str("interrupted (Ctrl-C)"),
            HaltReason::TimeLimit { limit_s: _ } => {
                f.write_str("stopped at the time limit (--max-seconds)")
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_halt_reason_has_the_words_of_the_json() {
        assert_eq!(HaltReason::Interrupted.to_string(), "interrupted (Ctrl-C)");
        assert_eq!(
            HaltReason::TimeLimit { limit_s: 0.3 }.to_string(),
            "stopped at the time limit (--max-seconds)"
        );
    }
}
