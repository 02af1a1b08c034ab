//! Writes an experiment's measured figures into `docs/measured.md`, the one
//! file whose figures no one edits by hand (the format of
//! `scripts/measured.py`): a section lies between
//! `<!-- measured:NAME (COMMAND) -->` and `<!-- /measured:NAME -->` and is
//! rewritten whole by the experiment that measures it.
//!
//! An experiment records only when it ran whole: with
//! `DEPLOYWATCH_FULL=1` and none of the variables that pick a subset of its
//! cases ([`SUBSET_VARS`]); a partial run prints its table and leaves the
//! file alone.

use std::path::PathBuf;

/// The variables that run a subset of an experiment's cases: a run with
/// any of them set is not a measurement of the whole.
pub const SUBSET_VARS: [&str; 4] = [
    "DEPLOYWATCH_FROM",
    "DEPLOYWATCH_CASE",
    "DEPLOYWATCH_FAMILY",
    "DEPLOYWATCH_SEED",
];

/// `docs/measured.md` in the repository.
pub fn measured_md() -> PathBuf {
    crate::repo_root().join("docs").join("measured.md")
}

/// Whether this run is a whole experiment whose figures are recorded:
/// `DEPLOYWATCH_FULL=1` and no subset variable set.
pub fn recording() -> bool {
    std::env::var("DEPLOYWATCH_FULL").is_ok_and(|v| v == "1")
        && SUBSET_VARS.iter().all(|v| std::env::var_os(v).is_none())
}

/// Today's date (UTC) as `YYYY-MM-DD`, from the system clock (Hinnant's
/// civil-from-days algorithm).
pub fn today() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_secs())
        .unwrap_or(0);
    let z = (secs / 86_400) as i64 + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!("{year:04}-{month:02}-{day:02}")
}

/// The section `name` of `docs/measured.md` as it would be written: `body`
/// (Markdown, starting with its `## ` heading), then the date and the
/// command, between the markers.
pub fn section(name: &str, command: &str, body: &str) -> String {
    format!(
        "<!-- measured:{name} ({command}) -->\n{}\n\n_Measured {} by `{command}`._\n<!-- /measured:{name} -->",
        body.trim_end(),
        today()
    )
}

/// `text` with the section `name` replaced by `block`, or `block`
/// appended when the file has no such section yet.
pub fn splice(text: &str, name: &str, block: &str) -> String {
    let start = format!("<!-- measured:{name} ");
    let end = format!("<!-- /measured:{name} -->");
    match (text.find(&start), text.find(&end)) {
        (Some(a), Some(b)) if b > a => {
            format!("{}{block}{}", &text[..a], &text[b + end.len()..])
        }
        _ => format!("{}\n\n{block}\n", text.trim_end()),
    }
}

/// Prints the section and, when [`recording`], writes it into
/// `docs/measured.md` (the rest of the file untouched).
pub fn record(name: &str, command: &str, body: &str) -> std::io::Result<()> {
    let block = section(name, command, body);
    println!("{block}");
    if !recording() {
        println!("(a partial or CI run: docs/measured.md left as it is)");
        return Ok(());
    }
    let path = measured_md();
    let text = std::fs::read_to_string(&path)?;
    std::fs::write(&path, splice(&text, name, &block))?;
    println!("recorded in {}", path.display());
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_section_is_replaced_in_place_and_appended_when_new() {
        let text = "# M\n\n<!-- measured:a (x) -->\nold\n<!-- /measured:a -->\n\n<!-- measured:b (y) -->\nkeep\n<!-- /measured:b -->\n";
        let out = splice(
            text,
            "a",
            "<!-- measured:a (x) -->\nnew\n<!-- /measured:a -->",
        );
        assert!(out.contains("new") && !out.contains("old") && out.contains("keep"));
        assert!(out.find("new") < out.find("keep"), "{out}");
        let out = splice(
            &out,
            "c",
            "<!-- measured:c (z) -->\nc\n<!-- /measured:c -->",
        );
        assert!(out.ends_with("<!-- /measured:c -->\n"), "{out}");
    }

    #[test]
    fn the_date_is_a_calendar_date() {
        let d = today();
        let parts: Vec<u32> = d.split('-').filter_map(|p| p.parse().ok()).collect();
        assert_eq!(parts.len(), 3, "{d}");
        assert!(parts[0] >= 2024 && (1..=12).contains(&parts[1]) && (1..=31).contains(&parts[2]));
    }
}
