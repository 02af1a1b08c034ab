//! Numbers written for people.

/// Numbers as a comma-separated list for people: `1.6, 1.6, 0`.
pub fn list<T: std::fmt::Display>(v: &[T]) -> String {
    v.iter()
        .map(|x| x.to_string())
        .collect::<Vec<_>>()
        .join(", ")
}

/// The things numbered 1 to `n`, in words for a message: `joints 1 to 3`,
/// `only joint 1` when there is one, `no joint` when there is none
/// (`one`, `many`: the noun in the singular and the plural).
pub fn one_to(n: usize, one: &str, many: &str) -> String {
    match n {
        0 => format!("no {one}"),
        1 => format!("only {one} 1"),
        n => format!("{many} 1 to {n}"),
    }
}

/// Numbers to four significant digits, trailing zeros dropped, as a
/// comma-separated list: `0.01051, 1.6, 0`.
pub fn list_4(v: &[f64]) -> String {
    v.iter()
        .map(|&x| significant_4(x))
        .collect::<Vec<_>>()
        .join(", ")
}

/// `x` to four significant digits, trailing zeros dropped (`1.6`, `0.01051`).
fn significant_4(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return x.to_string();
    }
    let decimals = (3 - x.abs().log10().floor() as i32).max(0) as usize;
    let s = format!("{x:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    use super::{list_4, one_to};

    #[test]
    fn a_range_of_one_is_not_written_1_to_1() {
        assert_eq!(one_to(3, "joint", "joints"), "joints 1 to 3");
        assert_eq!(one_to(1, "joint", "joints"), "only joint 1");
        assert_eq!(one_to(0, "bar", "bars"), "no bar");
    }

    #[test]
    fn four_significant_digits_without_trailing_zeros() {
        assert_eq!(
            list_4(&[
                0.010511205190671433,
                1.6,
                0.0,
                0.5656854249492381,
                1234.56,
                -0.25
            ]),
            "0.01051, 1.6, 0, 0.5657, 1235, -0.25"
        );
    }
}
