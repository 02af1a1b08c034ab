//! Progress of long work, as one convention for every library function that
//! takes time (simulations by the dozen in `identify`, `diagnose`): the
//! library never prints; it calls a [`Progress`] sink with one line of words
//! per step, and the command line decides where it goes (`stderr`, or
//! nowhere with `--quiet`).

/// A progress sink: called with one human-readable line per step.
pub type Progress<'a> = &'a (dyn Fn(&str) + Sync);

/// A progress sink that drops everything.
pub fn quiet(_: &str) {}

/// A progress sink that prints each line on standard error.
pub fn stderr(line: &str) {
    eprintln!("{line}");
}
