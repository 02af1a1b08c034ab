//! Computations that reproduce the seed papers' own tables, apart from the
//! simulator: the truss-link synthesis of seed 000 (Eqs. 2–10).
pub mod truss_synthesis;
