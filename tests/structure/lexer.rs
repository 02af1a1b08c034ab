//! The source text as the structure checks read it: comments, strings and
//! char literals blanked (newlines kept), `#[cfg(test)]` modules left out.

/// The text with comments, strings and char literals blanked (newlines
/// kept, so line numbers hold).
pub fn strip(text: &str) -> String {
    let b: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        let next = b.get(i + 1).copied().unwrap_or(' ');
        if c == '/' && next == '/' {
            while i < b.len() && b[i] != '\n' {
                i += 1;
            }
        } else if c == '/' && next == '*' {
            let mut depth = 0;
            while i < b.len() {
                if b[i] == '/' && b.get(i + 1) == Some(&'*') {
                    depth += 1;
                    i += 2;
                } else if b[i] == '*' && b.get(i + 1) == Some(&'/') {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    if b[i] == '\n' {
                        out.push('\n');
                    }
                    i += 1;
                }
            }
        } else if c == '"' || (c == 'r' && (next == '"' || next == '#') && raw_start(&b, i)) {
            i = skip_string(&b, i, &mut out);
        } else if c == '\'' && is_char_literal(&b, i) {
            i = skip_char(&b, i);
            out.push(' ');
        } else {
            out.push(c);
            i += 1;
        }
    }
    out
}

/// True when `r` at `i` opens a raw string (`r"…"`, `r#"…"#`), not an
/// identifier ending in `r`.
fn raw_start(b: &[char], i: usize) -> bool {
    let prev_ident = i > 0 && (b[i - 1].is_alphanumeric() || b[i - 1] == '_');
    if prev_ident {
        return false;
    }
    let mut j = i + 1;
    while j < b.len() && b[j] == '#' {
        j += 1;
    }
    j < b.len() && b[j] == '"'
}

/// Skips a (raw) string literal from `i`, keeping its newlines.
fn skip_string(b: &[char], mut i: usize, out: &mut String) -> usize {
    let mut hashes = 0;
    let raw = b[i] == 'r';
    if raw {
        i += 1;
        while b[i] == '#' {
            hashes += 1;
            i += 1;
        }
    }
    i += 1;
    while i < b.len() {
        if b[i] == '\n' {
            out.push('\n');
        }
        if !raw && b[i] == '\\' {
            i += 2;
            continue;
        }
        if b[i] == '"' && (0..hashes).all(|k| b.get(i + 1 + k) == Some(&'#')) {
            return i + 1 + hashes;
        }
        i += 1;
    }
    i
}

/// True when `'` at `i` opens a char literal rather than a lifetime.
fn is_char_literal(b: &[char], i: usize) -> bool {
    matches!(
        (b.get(i + 1), b.get(i + 2)),
        (Some('\\'), _) | (Some(_), Some('\''))
    )
}

fn skip_char(b: &[char], mut i: usize) -> usize {
    i += 1;
    if b.get(i) == Some(&'\\') {
        i += 1;
    }
    while i < b.len() && b[i] != '\'' {
        i += 1;
    }
    i + 1
}

/// Removes `#[cfg(test)]` inline modules from stripped text (lines kept)
/// and returns the names of `#[cfg(test)] mod x;` file modules.
pub fn drop_test_modules(stripped: &str) -> (String, Vec<String>) {
    let mut out = stripped.to_string();
    let mut test_files = Vec::new();
    let mut from = 0;
    while let Some(at) = out[from..].find("#[cfg(test)]") {
        let start = from + at;
        let rest = &out[start + 12..];
        let trimmed = rest.trim_start();
        let Some(after_mod) = trimmed
            .strip_prefix("mod ")
            .or_else(|| trimmed.strip_prefix("pub mod "))
            .or_else(|| trimmed.strip_prefix("pub(crate) mod "))
        else {
            from = start + 12;
            continue;
        };
        let name: String = after_mod
            .trim_start()
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        let after_name = after_mod.trim_start()[name.len()..].trim_start();
        if after_name.starts_with(';') {
            test_files.push(name);
            from = start + 12;
            continue;
        }
        let open = start + out[start..].find('{').unwrap();
        let close = matching_brace(&out, open);
        let blanked: String = out[start..close]
            .chars()
            .map(|c| if c == '\n' { '\n' } else { ' ' })
            .collect();
        out.replace_range(start..close, &blanked);
        from = close;
    }
    (out, test_files)
}

/// The index just past the `}` that closes the `{` at `open`.
pub fn matching_brace(s: &str, open: usize) -> usize {
    let mut depth = 0i32;
    for (k, c) in s[open..].char_indices() {
        match c {
            '{' => depth += 1,
            '}' => {
                depth -= 1;
                if depth == 0 {
                    return open + k + 1;
                }
            }
            _ => {}
        }
    }
    s.len()
}
