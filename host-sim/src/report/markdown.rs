//! Markdown written for people and read by any renderer: links to the
//! files a report sits beside, and tables.

/// The link target of a file beside the report: its name with every byte
/// outside the unreserved set of RFC 3986 (letters, digits, `-._~`)
/// percent-encoded, so a name with a space, parentheses or non-ASCII
/// letters stays one link in every Markdown renderer (CommonMark §6.3
/// ends a bare link destination at a space).
pub fn link_target(file_name: &str) -> String {
    let mut out = String::with_capacity(file_name.len());
    for b in file_name.bytes() {
        if b.is_ascii_alphanumeric() || b"-._~".contains(&b) {
            out.push(char::from(b));
        } else {
            out.push_str(&format!("%{b:02X}"));
        }
    }
    out
}

/// An image of the report: `![alt](target)` with the file's name as its
/// [`link_target`].
pub fn image(alt: &str, file_name: &str) -> String {
    format!("![{alt}]({})", link_target(file_name))
}

/// The file name of `path`, for a link from a report in the same folder.
pub fn file_name(path: &std::path::Path) -> String {
    path.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_with_spaces_and_brackets_stay_one_link() {
        assert_eq!(
            image("angles", "my run (2).png"),
            "![angles](my%20run%20%282%29.png)"
        );
        assert_eq!(link_target("diagnosis_T01.png"), "diagnosis_T01.png");
        assert_eq!(link_target("Lauf_ä.png"), "Lauf_%C3%A4.png");
    }
}

/// A table: the header row, its separator and one row per entry of
/// `rows` (each cell as given; a `|` in a cell is the caller's to escape),
/// every line ended by a newline.
pub fn table<R: AsRef<[String]>>(head: &[&str], rows: impl IntoIterator<Item = R>) -> String {
    let line = |cells: &mut dyn Iterator<Item = &str>| {
        let mut l = String::from("|");
        for c in cells {
            l.push(' ');
            l.push_str(c);
            l.push_str(" |");
        }
        l.push('\n');
        l
    };
    let mut out = line(&mut head.iter().copied());
    out.push('|');
    out.push_str(&"---|".repeat(head.len()));
    out.push('\n');
    for r in rows {
        out.push_str(&line(&mut r.as_ref().iter().map(String::as_str)));
    }
    out
}

#[cfg(test)]
mod table_tests {
    use super::table;

    #[test]
    fn a_table_has_its_header_separator_and_rows() {
        let t = table(&["a", "b"], [vec!["1".to_string(), "2".to_string()]]);
        assert_eq!(t, "| a | b |\n|---|---|\n| 1 | 2 |\n");
        assert_eq!(table(&["x"], Vec::<Vec<String>>::new()), "| x |\n|---|\n");
    }
}
