//! What an input file holds, read off its first line: a run CSV, a
//! mechanism TOML or a JSON document (`docs/spec/formats.md`). A loader
//! that meets the wrong one says which it met: a new user swaps
//! `--mechanism M.toml` and the run, or gives a command's `--json` output
//! where a mechanism belongs.

use std::fmt;

/// A kind of input file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FileKind {
    /// A run CSV: its header starts `t_s,`.
    RunCsv,
    /// A mechanism TOML: a `key = value` line or a `[table]` header.
    MechanismToml,
    /// A JSON document: it opens with `{`.
    Json,
}

impl FileKind {
    /// The kind the file's first line that is neither blank nor a `#`
    /// comment suggests ([`FileKind::first_line`], [`FileKind::of_line`]).
    pub fn of_text(text: &str) -> Option<FileKind> {
        Self::first_line(text).and_then(|(_, l)| Self::of_line(l))
    }

    /// The first line of `text` that is neither blank nor a `#` comment,
    /// trimmed, with its 1-based number.
    pub fn first_line(text: &str) -> Option<(usize, &str)> {
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        text.lines()
            .map(str::trim)
            .enumerate()
            .find(|(_, l)| !l.is_empty() && !l.starts_with('#'))
            .map(|(i, l)| (i + 1, l))
    }

    /// The kind a file's first line (not blank, not a comment) suggests;
    /// `None` when it suggests none of them.
    pub fn of_line(line: &str) -> Option<FileKind> {
        let line = line.trim();
        let key = |k: &str| {
            let k = k.trim();
            !k.is_empty()
                && k.chars()
                    .all(|c| c.is_ascii_alphanumeric() || "_-.\"'".contains(c))
        };
        // What a TOML value starts as: a string, an array, an inline table,
        // a boolean or a number (not a spreadsheet's `sep=,` line).
        let value = |v: &str| {
            let v = v.trim();
            v.starts_with(['"', '\'', '[', '{'])
                || v == "true"
                || v == "false"
                || v.replace('_', "").parse::<f64>().is_ok()
        };
        if line.starts_with('{') {
            Some(FileKind::Json)
        } else if line == "t_s" || line.starts_with("t_s,") || line.starts_with("t_s;") {
            Some(FileKind::RunCsv)
        } else if (line.starts_with('[') && line.ends_with(']'))
            || line
                .split_once('=')
                .is_some_and(|(k, v)| key(k) && value(v))
        {
            Some(FileKind::MechanismToml)
        } else {
            None
        }
    }
}

impl fmt::Display for FileKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            FileKind::RunCsv => "a run CSV (its header starts `t_s,`)",
            FileKind::MechanismToml => "a mechanism TOML (`key = value` lines, `[table]` headers)",
            FileKind::Json => "a JSON document (a command's `--json` output?)",
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_line_tells_the_kind() {
        let cases = [
            (
                "# mechanism = \"T01\"\nt_s,phi1_deg,latch1\n0,1,0\n",
                Some(FileKind::RunCsv),
            ),
            ("\u{feff}t_s;phi1_deg;latch1\n", Some(FileKind::RunCsv)),
            (
                "# a wing\n\nname = \"seed001-T01\"\n",
                Some(FileKind::MechanismToml),
            ),
            ("[[panel]]\nlength_m = 1\n", Some(FileKind::MechanismToml)),
            ("  {\"effects\": []}", Some(FileKind::Json)),
            ("time,angle\n", None),
            ("sep=,\nt_s,phi1_deg,latch1\n", None),
            ("duration_s = 6.0\n", Some(FileKind::MechanismToml)),
            ("", None),
        ];
        for (text, kind) in cases {
            assert_eq!(FileKind::of_text(text), kind, "{text:?}");
        }
    }
}
