//! The spreadsheet dialect of the run CSV.
