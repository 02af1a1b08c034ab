//! The host side of the `torque_table` effect (`docs/spec/physics.md`
//! section 6; the torque itself is computed once, in
//! [`deploywatch_core::TorqueTable`]): its points as written in the
//! `--effect` syntax and in a diagnosis JSON, and a one-sentence description
//! of its shape.
//!
//! `--effect torque_table:joint=J:angle_deg=A1,A2,..:torque_nm=T1,T2,..`
//! `[:rate_deg_s=R1,R2,..:rate_torque_nm=G1,G2,..]` (either table or both).

use deploywatch_core::{Table, TableError as CoreTableError, TorqueTable};

/// Most points of one table on the host \[1\]: the host simulator and the
/// diagnosis hold tables this large (a hump of a rate law or a dip over
/// part of the stroke needs more knots than the monitor's
/// [`deploywatch_core::physics::TABLE_MAX_KNOTS`]); a table for the
/// monitor is a compressed export of 8 points, made by the diagnosis with
/// its fit loss (`docs/diagnosis.md`).
pub const HOST_TABLE_MAX_KNOTS: usize = 24;

/// One piecewise-linear table as the host holds it.
pub type HostTable = Table<f64, HOST_TABLE_MAX_KNOTS>;

/// A joint's `torque_table` as the host holds it.
pub type HostTorqueTable = TorqueTable<f64, HOST_TABLE_MAX_KNOTS>;

/// A joint's named effects as the host simulator holds them.
pub type HostJointEffects = deploywatch_core::JointEffects<f64, HOST_TABLE_MAX_KNOTS>;

/// The core chain of `N` joints as the host simulator integrates it
/// (`f64`, tables of up to [`HOST_TABLE_MAX_KNOTS`] points).
pub type HostChain<const N: usize> = deploywatch_core::Chain<f64, N, HOST_TABLE_MAX_KNOTS>;

/// What is wrong with the points of a torque table.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum TableError {
    /// A list that is not numbers separated by commas.
    #[error("`{key}={value}`: expected numbers separated by commas")]
    BadNumberList {
        /// The key.
        key: String,
        /// The list as written.
        value: String,
    },
    /// Abscissae and values of unequal length.
    #[error("{x_key} and {y_key} must have as many points")]
    UnequalLengths {
        /// The abscissae's key (`angle_deg` or `rate_deg_s`).
        x_key: &'static str,
        /// The values' key (`torque_nm` or `rate_torque_nm`).
        y_key: &'static str,
    },
    /// Only one list of a pair given.
    #[error("{x_key} and {y_key} go together: give both")]
    HalfPair {
        /// The abscissae's key (`angle_deg` or `rate_deg_s`).
        x_key: &'static str,
        /// The values' key (`torque_nm` or `rate_torque_nm`).
        y_key: &'static str,
    },
    /// Neither pair given.
    #[error("torque_table needs angle_deg/torque_nm, rate_deg_s/rate_torque_nm or both")]
    NoTable,
    /// A pair the core refuses as a table (too few or too many points,
    /// abscissae not increasing, numbers not finite).
    #[error("{x_key}/{y_key}: {source}")]
    Core {
        /// The abscissae's key (`angle_deg` or `rate_deg_s`).
        x_key: &'static str,
        /// The values' key (`torque_nm` or `rate_torque_nm`).
        y_key: &'static str,
        /// The core's reason.
        #[source]
        source: CoreTableError,
    },
}

/// The four point lists of a torque table as they are written, before they
/// are checked and built.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TablePoints {
    /// `angle_deg`: abscissae of `f` \[deg\].
    pub angle_deg: Option<Vec<f64>>,
    /// `torque_nm`: `f` at those angles [N·m].
    pub torque_nm: Option<Vec<f64>>,
    /// `rate_deg_s`: abscissae of `g` [deg/s].
    pub rate_deg_s: Option<Vec<f64>>,
    /// `rate_torque_nm`: `g` at those rates [N·m].
    pub rate_torque_nm: Option<Vec<f64>>,
}

impl TablePoints {
    /// Takes `key=value` when `key` is one of the four table keys; returns
    /// `Ok(false)` for any other key.
    pub fn take(&mut self, key: &str, value: &str) -> Result<bool, TableError> {
        let slot = match key {
            "angle_deg" => &mut self.angle_deg,
            "torque_nm" => &mut self.torque_nm,
            "rate_deg_s" => &mut self.rate_deg_s,
            "rate_torque_nm" => &mut self.rate_torque_nm,
            _ => return Ok(false),
        };
        let list = value
            .split(',')
            .map(|x| x.trim().parse::<f64>())
            .collect::<Result<Vec<f64>, _>>()
            .map_err(|_| TableError::BadNumberList {
                key: key.to_string(),
                value: value.to_string(),
            })?;
        *slot = Some(list);
        Ok(true)
    }

    /// True when no table key was given.
    pub fn is_empty(&self) -> bool {
        *self == TablePoints::default()
    }

    /// Builds the table: each of `f` and `g` needs both its lists, of equal
    /// length, abscissae strictly increasing; at least one of them.
    pub fn build(&self) -> Result<HostTorqueTable, TableError> {
        let one = |x: &Option<Vec<f64>>,
                   y: &Option<Vec<f64>>,
                   x_key: &'static str,
                   y_key: &'static str| match (x, y) {
            (None, None) => Ok(None),
            (Some(x), Some(y)) if x.len() == y.len() => {
                Table::new(x, y)
                    .map(Some)
                    .map_err(|source| TableError::Core {
                        x_key,
                        y_key,
                        source,
                    })
            }
            (Some(_), Some(_)) => Err(TableError::UnequalLengths { x_key, y_key }),
            _ => Err(TableError::HalfPair { x_key, y_key }),
        };
        let t = TorqueTable {
            angle: one(&self.angle_deg, &self.torque_nm, "angle_deg", "torque_nm")?,
            rate: one(
                &self.rate_deg_s,
                &self.rate_torque_nm,
                "rate_deg_s",
                "rate_torque_nm",
            )?,
        };
        if t.angle.is_none() && t.rate.is_none() {
            return Err(TableError::NoTable);
        }
        Ok(t)
    }
}

/// `a,b,c` of a list, shortest round-trip form of each number (the
/// syntax of a table's keys).
pub fn list(v: &[f64]) -> String {
    v.iter()
        .map(|x| x.to_string())
        .collect::<Vec<_>>()
        .join(",")
}

/// The largest absolute torque of either table [N·m] (the `value` a
/// diagnosis reports beside the tables).
pub fn max_abs_nm<const K: usize>(t: &TorqueTable<f64, K>) -> f64 {
    [&t.angle, &t.rate]
        .into_iter()
        .flatten()
        .flat_map(|tab| tab.ys().iter().map(|y| y.abs()))
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn given_points_when_built_then_keys_round_trip() {
        let mut p = TablePoints::default();
        assert!(p.take("angle_deg", "-90,-45,0").unwrap());
        assert!(p.take("torque_nm", "0,0.3,-0.1").unwrap());
        assert!(!p.take("joint", "1").unwrap());
        let t = p.build().unwrap();
        let f = t.angle.as_ref().unwrap();
        assert_eq!(
            (list(f.xs()), list(f.ys())),
            ("-90,-45,0".into(), "0,0.3,-0.1".into())
        );
        assert_eq!(max_abs_nm(&t), 0.3);
    }

    #[test]
    fn given_bad_points_then_the_error_names_the_keys() {
        let mut p = TablePoints::default();
        p.take("rate_deg_s", "0,10").unwrap();
        let e = p.build().unwrap_err();
        assert!(matches!(e, TableError::HalfPair { .. }));
        assert!(e.to_string().contains("rate_torque_nm"));
        p.take("rate_torque_nm", "1").unwrap();
        let e = p.build().unwrap_err();
        assert!(matches!(e, TableError::UnequalLengths { .. }));
        assert!(e.to_string().contains("as many points"));
        assert!(matches!(
            p.take("angle_deg", "a,b"),
            Err(TableError::BadNumberList { .. })
        ));
        assert_eq!(TablePoints::default().build(), Err(TableError::NoTable));
        let mut q = TablePoints::default();
        q.take("angle_deg", "0").unwrap();
        q.take("torque_nm", "1").unwrap();
        assert!(matches!(q.build(), Err(TableError::Core { .. })));
    }
}
