//! The progress of `deploywatch diagnose` on the terminal.

/// The progress of a long search on standard error: on a terminal, each
/// step's line printed above a spinner that shows the elapsed time and the
/// current step; otherwise (a log file) the lines alone; nothing with
/// `--quiet`.
pub struct Spinner {
    bar: Option<indicatif::ProgressBar>,
    quiet: bool,
}

impl Spinner {
    /// A spinner, drawn only when standard error is a terminal.
    pub fn new(quiet: bool) -> Spinner {
        use std::io::IsTerminal;
        let bar = (!quiet && std::io::stderr().is_terminal()).then(|| {
            let b = indicatif::ProgressBar::new_spinner();
            b.set_style(
                indicatif::ProgressStyle::with_template(
                    "{spinner} {elapsed_precise} {wide_msg} (Ctrl-C: stop and keep the best so far)",
                )
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_spinner()),
            );
            b.enable_steady_tick(std::time::Duration::from_millis(200));
            b
        });
        Spinner { bar, quiet }
    }

    /// One step's line.
    pub fn line(&self, line: &str) {
        if self.quiet {
            return;
        }
        match &self.bar {
            Some(b) => {
                b.println(line);
                b.set_message(line.trim().to_string());
            }
            None => eprintln!("{line}"),
        }
    }

    /// Clears the spinner.
    pub fn finish(&self) {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
    }
}
