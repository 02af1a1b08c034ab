//! Correlated parameters: a Gaussian copula. `--corr I,J,RHO` sets the
//! correlation of the standard normals behind parameters `I` and `J`
//! (1-based, in the order of the `--vary`, then `--from`); the independent
//! normals `u` of the algorithms map to `z = L u` with `L Lᵀ = R` (Cholesky),
//! then each parameter to `x_i = F_i⁻¹(Φ(z_i))` (the Nataf model, with `R`
//! the correlation of the normals, not of the parameters).

use nalgebra::DMatrix;
use std::fmt;
use std::str::FromStr;

/// One `--corr I,J,RHO`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Correlation {
    /// 1-based parameter.
    pub i: usize,
    /// 1-based parameter, not `i`.
    pub j: usize,
    /// Correlation of their standard normals, in (−1, 1).
    pub rho: f64,
}

/// Why a correlation (`I,J,RHO`) was rejected.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{0}: expected I,J,RHO: two different parameters (1-based, in the order of the laws drawn, then the effects carried from findings) and a correlation in (-1, 1)")]
pub struct CorrelationError(pub String);

impl FromStr for Correlation {
    type Err = CorrelationError;
    fn from_str(s: &str) -> Result<Self, CorrelationError> {
        let bad = || CorrelationError(s.to_string());
        let parts: Vec<&str> = s.split(',').map(str::trim).collect();
        let [i, j, rho] = parts[..] else {
            return Err(bad());
        };
        let i: usize = i.parse().map_err(|_| bad())?;
        let j: usize = j.parse().map_err(|_| bad())?;
        let rho: f64 = rho.parse().map_err(|_| bad())?;
        if i == 0 || j == 0 || i == j || !(rho > -1.0 && rho < 1.0) {
            return Err(bad());
        }
        Ok(Correlation { i, j, rho })
    }
}

impl fmt::Display for Correlation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{},{},{}", self.i, self.j, self.rho)
    }
}

/// Why the correlations of `d` parameters cannot be used.
#[derive(Clone, Debug, PartialEq)]
pub enum CholeskyError {
    /// A correlation names a parameter beyond the `d` drawn.
    Beyond {
        /// The correlation.
        corr: Correlation,
        /// The parameters drawn.
        d: usize,
    },
    /// The correlation matrix is not positive definite.
    NotPositiveDefinite,
    /// One pair of parameters given two different correlations.
    Twice {
        /// The first given.
        first: Correlation,
        /// The other.
        second: Correlation,
    },
}

/// The lower Cholesky factor `L` of the correlation matrix of `d`
/// parameters (`None` without correlations: `L = I`).
pub fn cholesky(corr: &[Correlation], d: usize) -> Result<Option<DMatrix<f64>>, CholeskyError> {
    if corr.is_empty() {
        return Ok(None);
    }
    let mut r = DMatrix::<f64>::identity(d, d);
    for (k, c) in corr.iter().enumerate() {
        if c.i > d || c.j > d {
            return Err(CholeskyError::Beyond { corr: *c, d });
        }
        let pair = |x: &Correlation| (x.i.min(x.j), x.i.max(x.j));
        if let Some(first) = corr[..k]
            .iter()
            .find(|x| pair(x) == pair(c) && x.rho != c.rho)
        {
            return Err(CholeskyError::Twice {
                first: *first,
                second: *c,
            });
        }
        r[(c.i - 1, c.j - 1)] = c.rho;
        r[(c.j - 1, c.i - 1)] = c.rho;
    }
    r.cholesky()
        .map(|ch| Some(ch.l()))
        .ok_or(CholeskyError::NotPositiveDefinite)
}

/// `z = L u`.
pub fn correlate(l: &DMatrix<f64>, u: &[f64]) -> Vec<f64> {
    (0..u.len())
        .map(|i| (0..=i).map(|k| l[(i, k)] * u[k]).sum())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_pair_given_two_correlations_is_refused() {
        let c = |s: &str| s.parse::<Correlation>().unwrap();
        let twice = cholesky(&[c("1,2,0.5"), c("2,1,-0.5")], 2);
        assert!(
            matches!(twice, Err(CholeskyError::Twice { .. })),
            "{twice:?}"
        );
        assert!(cholesky(&[c("1,2,0.5"), c("2,1,0.5")], 2).is_ok());
    }

    #[test]
    fn correlates_the_normals() {
        let c: Correlation = "1,2,0.8".parse().unwrap();
        assert_eq!(
            c,
            Correlation {
                i: 1,
                j: 2,
                rho: 0.8
            }
        );
        for bad in ["1,1,0.5", "1,2,1", "0,2,0.1", "1,2", "a,2,0.1"] {
            assert!(bad.parse::<Correlation>().is_err(), "{bad}");
        }
        let l = cholesky(&[c], 2).unwrap().unwrap();
        let z = correlate(&l, &[1.0, 0.0]);
        assert_eq!(z, vec![1.0, 0.8]);
        let z = correlate(&l, &[0.0, 1.0]);
        assert!((z[1] - 0.6).abs() < 1e-15 && z[0] == 0.0);
        assert_eq!(
            cholesky(&[c], 1),
            Err(CholeskyError::Beyond { corr: c, d: 1 })
        );
        let three = ["1,2,0.9", "2,3,0.9", "1,3,-0.9"].map(|t| t.parse().unwrap());
        assert!(cholesky(&three, 3).is_err(), "not positive definite");
        assert!(matches!(cholesky(&[], 3), Ok(None)));
    }
}
