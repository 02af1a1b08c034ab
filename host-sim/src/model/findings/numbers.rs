//! The numbers of the findings JSON: rounding for writing (the model's
//! parameters in full), and `null` (a
//! number that was not finite) read back as NaN.

use serde::{Deserialize, Deserializer};

/// Reads a number written by serde_json, `null` (a number that was not
/// finite) as NaN.
pub fn nan_if_null<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

/// [`nan_if_null`] for each number of a list.
pub fn nans_if_null<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<f64>, D::Error> {
    Ok(Vec::<Option<f64>>::deserialize(d)?
        .into_iter()
        .map(|x| x.unwrap_or(f64::NAN))
        .collect())
}

/// NaN: a number a file does not give.
pub fn not_given() -> f64 {
    f64::NAN
}

/// Decimals of the numbers of a diagnosis: 6 ([`rounded`]).
pub const ROUNDING: f64 = 1e6;

/// `x` as it is, `None` (written as `null`) when it is not finite: a
/// parameter of the model a diagnosis found (an effect's value, a table's
/// knots), written in full (serde_json writes the shortest decimal that
/// reads back to the same `f64`), so that the model read back from the
/// file is the one fitted, bit for bit.
pub fn exact(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}

/// `x` rounded to 6 decimals ([`ROUNDING`]) for a findings file, `None`
/// (written as `null`) when it is not finite.
pub fn rounded(x: f64) -> Option<f64> {
    x.is_finite().then(|| (x * ROUNDING).round() / ROUNDING)
}
