//! Numbers as the reliability analysis prints them for a reader: six
//! significant digits and the unit (`1.40769 N·m`, `8.14105 s`); the JSON
//! keeps every digit.

/// Significant digits of the printed parameters and thresholds.
pub const DIGITS: usize = 6;

/// `x` to [`DIGITS`] significant digits, trailing zeros dropped
/// (`0.932126`, `2.63`, `1e-9`, `-1.23457e7`).
pub fn sig(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let trim = |t: &str| -> String {
        if t.contains('.') {
            t.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            t.to_string()
        }
    };
    let e = x.abs().log10().floor() as i32;
    if (-4..DIGITS as i32).contains(&e) {
        let decimals = (DIGITS as i32 - 1 - e).max(0) as usize;
        trim(&format!("{x:.decimals$}"))
    } else {
        let t = format!("{x:.*e}", DIGITS - 1);
        let (m, exp) = t.split_once('e').unwrap_or((&t, "0"));
        format!("{}e{exp}", trim(m))
    }
}

/// `x unit` ([`sig`]; no unit for a dimensionless `1`).
pub fn quantity(x: f64, unit: &str) -> String {
    match unit {
        "1" => sig(x),
        _ => format!("{} {unit}", sig(x)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn six_significant_digits_and_no_trailing_zeros() {
        assert_eq!(sig(0.9321262344584399), "0.932126");
        assert_eq!(sig(2.63), "2.63");
        assert_eq!(sig(1e-9), "1e-9");
        assert_eq!(sig(1.8932718571419855), "1.89327");
        assert_eq!(sig(8.141048), "8.14105");
        assert_eq!(sig(-12345678.9), "-1.23457e7");
        assert_eq!(sig(0.0), "0");
        assert_eq!(sig(120.0), "120");
        assert_eq!(sig(0.00012345678), "0.000123457");
        assert_eq!(quantity(1.40769197242075, "N·m"), "1.40769 N·m");
        assert_eq!(quantity(0.05, "1"), "0.05");
    }
}
