//! What an input file holds, read off its first line: a run CSV, a
//! mechanism TOML or a JSON document (`docs/spec/formats.md`). A loader
//! that meets the wrong one says which it met: a new user swaps
//! `--mechanism M.toml` and the run, or gives a command's `--json` output
//! where a mechanism belongs. A file that is not UTF-8 is told where it
//! stops being UTF-8 and what it looks like instead ([`utf8_text`]).

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

/// Smallest share of a file's bytes that are printable ASCII, tab, CR or
/// LF for a file that is not UTF-8 to be taken for text in another
/// encoding (0.9): a German or French text in Latin-1 has a few per cent of
/// bytes above 127, a binary file (an image, an archive) mostly such bytes
/// and controls.
pub const MIN_TEXT_SHARE: f64 = 0.9;

/// The UTF-16 byte-order marks, as the bytes a file starts with and as
/// written in a message: little-endian (a spreadsheet's "Unicode text" on
/// Windows), big-endian.
const UTF16_MARKS: [([u8; 2], &str); 2] = [([0xFF, 0xFE], "FF FE"), ([0xFE, 0xFF], "FE FF")];

/// What the bytes of a file that is not UTF-8 likely are.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Encoding {
    /// UTF-16 text: the byte-order mark it starts with (`FF FE`).
    Utf16 {
        /// The mark, as written in a message.
        mark: &'static str,
    },
    /// Text in a one-byte code page (Latin-1, Windows-1252): the first byte
    /// that is not UTF-8.
    SingleByte {
        /// The byte.
        byte: u8,
    },
    /// No text: fewer than [`MIN_TEXT_SHARE`] of its bytes are.
    Binary,
}

/// Where a file stops being UTF-8, and what it likely is instead.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct NotUtf8 {
    /// 1-based line of the first byte that is not UTF-8.
    pub line: usize,
    /// 1-based column of that byte, in characters of its line.
    pub column: usize,
    /// Offset of that byte in the file, from 0.
    pub offset: usize,
    /// What the file likely is.
    pub encoding: Encoding,
}

/// The text of a file's `bytes`, or where it is not UTF-8 and what it
/// looks like instead.
pub fn utf8_text(bytes: Vec<u8>) -> Result<String, NotUtf8> {
    String::from_utf8(bytes).map_err(|e| {
        let offset = e.utf8_error().valid_up_to();
        let bytes = e.as_bytes();
        let before = std::str::from_utf8(&bytes[..offset]).unwrap_or_default();
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        let texty = bytes
            .iter()
            .filter(|&&b| matches!(b, b'\t' | b'\n' | b'\r' | 0x20..=0x7E))
            .count();
        let encoding =
            if let Some((_, mark)) = UTF16_MARKS.iter().find(|(m, _)| bytes.starts_with(m)) {
                Encoding::Utf16 { mark }
            } else if texty as f64 >= MIN_TEXT_SHARE * bytes.len() as f64 {
                Encoding::SingleByte {
                    byte: bytes[offset],
                }
            } else {
                Encoding::Binary
            };
        NotUtf8 {
            line: 1 + before.matches('\n').count(),
            column: 1 + before[line_start..].chars().count(),
            offset,
            encoding,
        }
    })
}

impl fmt::Display for NotUtf8 {
    /// What the file is instead of UTF-8, after its `file:line:`; for a
    /// binary file, no more than that it is not text.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.encoding {
            Encoding::Utf16 { mark } => write!(
                f,
                "the file starts with the byte-order mark {mark} of UTF-16 text (a spreadsheet's \"Unicode text\"), not UTF-8"
            ),
            Encoding::SingleByte { byte } => {
                write!(f, "column {} (byte {}): byte 0x{byte:02X} is not UTF-8", self.column, self.offset)?;
                if let 0xA0..=0xFF = byte {
                    write!(f, " but `{}` in Latin-1 and Windows-1252", char::from(byte))?;
                }
                f.write_str(" (a file saved in Latin-1 or Windows-1252?)")
            }
            Encoding::Binary => write!(f, "not a text file (invalid UTF-8 at byte {})", self.offset),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_that_is_not_utf8_is_told_where_and_what_it_looks_like() {
        let latin1 = b"# mechanism = \"T01\"\n# source = \"Pr\xFCfstand\"\nt_s\n".to_vec();
        let e = utf8_text(latin1).expect_err("Latin-1");
        assert_eq!((e.line, e.column), (2, 15), "{e:?}");
        assert_eq!(e.encoding, Encoding::SingleByte { byte: 0xFC });
        assert!(
            e.to_string().contains("Latin-1") && e.to_string().contains("`ü`"),
            "{e}"
        );
        let utf16: Vec<u8> = [0xFF, 0xFE]
            .into_iter()
            .chain("t_s".bytes().flat_map(|b| [b, 0]))
            .collect();
        let e = utf8_text(utf16).expect_err("UTF-16");
        assert_eq!((e.line, e.column), (1, 1));
        assert!(
            e.to_string().contains("UTF-16") && e.to_string().contains("FF FE"),
            "{e}"
        );
        let binary: Vec<u8> = (0..64u8).map(|b| b | 0x80).collect();
        let e = utf8_text(binary).expect_err("binary");
        assert_eq!(e.encoding, Encoding::Binary);
        assert!(e.to_string().starts_with("not a text file"), "{e}");
        assert_eq!(utf8_text(b"t_s\n".to_vec()).as_deref(), Ok("t_s\n"));
    }

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
