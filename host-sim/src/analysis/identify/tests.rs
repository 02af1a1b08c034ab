//! Tests of `identify`.

use super::*;

#[test]
fn names_parse_and_print() {
    for m in [Method::Direct, Method::Rsm] {
        assert_eq!(m.name().parse::<Method>(), Ok(m));
    }
    for r in [RsmResponse::TeSum, RsmResponse::Mse] {
        assert_eq!(r.name().parse::<RsmResponse>(), Ok(r));
    }
    assert!("lm"
        .parse::<Method>()
        .unwrap_err()
        .to_string()
        .contains("direct"));
    assert_eq!(serde_json::to_string(&Method::Rsm).unwrap(), "\"rsm\"");
}

#[test]
fn option_vectors_are_checked() {
    assert!(check_vector("start", &[1.0, 2.0], 2, true).is_ok());
    let e = check_vector("centre", &[1.0], 2, true)
        .unwrap_err()
        .to_string();
    assert!(e.contains("centre") && e.contains("(2)"), "{e}");
    assert!(check_vector("range", &[-1.0, 1.0], 2, true).is_err());
    assert!(check_vector("range", &[f64::NAN, 1.0], 2, false).is_err());
}

#[test]
fn the_scan_grid_is_geometric() {
    for w in SCAN_GRID_NM[1..].windows(2) {
        assert!(
            (w[1] / w[0] - std::f64::consts::SQRT_2).abs() < 1e-4,
            "{w:?}"
        );
    }
}
