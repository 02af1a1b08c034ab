//! Where a resistance's value comes from, which selects the row of a
//! standard's factors (NASA-STD-5017B Table 1).

/// Where a resistance's value comes from: the standards' factors fall as
/// the knowledge grows (NASA-STD-5017B Table 1 rows).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum DataSource {
    /// Theory or analysis (initial sizing).
    #[default]
    Analysis,
    /// Development, qualification or lot-acceptance test, or acceptance
    /// test at ambient.
    Test,
    /// Acceptance test of the flight hardware at environmental extremes.
    AcceptanceExtremes,
}

impl DataSource {
    /// Every data source.
    pub const ALL: [DataSource; 3] = [
        DataSource::Analysis,
        DataSource::Test,
        DataSource::AcceptanceExtremes,
    ];

    /// The name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            DataSource::Analysis => "analysis",
            DataSource::Test => "test",
            DataSource::AcceptanceExtremes => "acceptance-extremes",
        }
    }

    /// The row of NASA-STD-5017B Table 1 it stands for.
    pub fn row(self) -> &'static str {
        match self {
            DataSource::Analysis => "theory or analysis",
            DataSource::Test => {
                "development, qualification, lot-acceptance test, or acceptance test at ambient"
            }
            DataSource::AcceptanceExtremes => "acceptance test at environmental extremes",
        }
    }
}
