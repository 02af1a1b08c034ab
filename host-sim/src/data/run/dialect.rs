//! The spreadsheet dialect of the run CSV (`docs/spec/formats.md`, "Run:
//! the spreadsheet dialect", the project's own extension): fields separated
//! by `;` and numbers with a decimal comma, as the spreadsheets of most
//! locales save "CSV". It is read by turning it into the comma dialect line
//! for line, so every error keeps its line number.

use std::borrow::Cow;

use super::error::shorten;
use super::error::{RunError, RunErrorKind};

/// The field separator of the spreadsheet dialect.
pub const SPREADSHEET_SEPARATOR: u8 = b';';

/// True when the header line (the first line not starting with `#`) is
/// separated by `;` and holds no `,`: the spreadsheet dialect.
fn is_spreadsheet(text: &str) -> bool {
    text.lines()
        .find(|l| !l.starts_with('#'))
        .is_some_and(|h| h.contains(';') && !h.contains(','))
}

/// The field separator of `text` as written: `;` in the spreadsheet
/// dialect, else `,`.
pub(super) fn separator(text: &str) -> char {
    if is_spreadsheet(text) {
        char::from(SPREADSHEET_SEPARATOR)
    } else {
        ','
    }
}

/// `text` in the comma dialect: itself when it is already, else the
/// spreadsheet dialect converted line for line (fields split by the `csv`
/// crate with `;` as delimiter, decimal commas made points, metadata lines
/// unquoted and stripped of the empty cells a spreadsheet pads them with).
pub(super) fn to_comma_dialect<'t>(text: &'t str, source: &str) -> Result<Cow<'t, str>, RunError> {
    if let Some((n, header)) = text
        .lines()
        .enumerate()
        .find(|(_, l)| !l.starts_with('#'))
        .filter(|(_, h)| h.contains('\t') && !h.contains(',') && !h.contains(';'))
    {
        let kind = RunErrorKind::BadLine {
            expected: "a header separated by `,` (or by `;`, the spreadsheet dialect); this one is tab-separated: save it as CSV".to_string(),
            found: shorten(header),
        };
        return Err(RunError::at(source, n + 1, kind));
    }
    if !is_spreadsheet(text) {
        return Ok(Cow::Borrowed(text));
    }
    let mut reader = csv::ReaderBuilder::new()
        .delimiter(SPREADSHEET_SEPARATOR)
        .has_headers(false)
        .flexible(true)
        .from_reader(text.as_bytes());
    let mut out = String::with_capacity(text.len());
    let mut line = 1;
    let mut record = csv::StringRecord::new();
    loop {
        let at = reader.position().line() as usize;
        let more = reader.read_record(&mut record).map_err(|e| {
            let kind = RunErrorKind::BadLine {
                expected: "a row of `;`-separated fields (the spreadsheet dialect)".to_string(),
                found: shorten(&e.to_string()),
            };
            RunError::at(source, at.max(line), kind)
        })?;
        if !more {
            break;
        }
        let start = record.position().map_or(line, |p| p.line() as usize);
        // Empty lines the reader skipped stay empty lines, errors of the
        // comma reader.
        while line < start {
            out.push('\n');
            line += 1;
        }
        out.push_str(&convert(&record));
        out.push('\n');
        line += 1;
    }
    Ok(Cow::Owned(out))
}

/// One record in the comma dialect: a metadata line as written (its cells
/// joined back by `;`, trailing empty cells dropped), else its fields with
/// decimal commas as points, joined by `,`.
fn convert(record: &csv::StringRecord) -> String {
    let fields: Vec<&str> = record.iter().collect();
    if fields.first().is_some_and(|f| f.starts_with('#')) {
        let used = fields
            .iter()
            .rposition(|f| !f.trim().is_empty())
            .map_or(0, |i| i + 1);
        return fields[..used].join(";");
    }
    fields
        .iter()
        .map(|f| f.trim().replace(',', "."))
        .collect::<Vec<_>>()
        .join(",")
}
