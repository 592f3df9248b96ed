//! Progress of long runs on stderr. indicatif hides its bars when stderr is not a user-attended
//! terminal, so pipes, logs and tests see nothing of them.

use indicatif::{ProgressBar, ProgressStyle};

/// A bar over `len` units named `unit`, with the estimated time left.
pub fn bar(len: u64, unit: &str) -> ProgressBar {
    styled(
        ProgressBar::new(len),
        &format!("{{bar:40}} {{pos}}/{{len}} {unit} ({{eta}})"),
    )
}

/// The stages of one command (reading, refining, writing…), shown as they start, with the time
/// spent so far.
pub struct Stages {
    bar: ProgressBar,
}

impl Stages {
    /// `count` stages; none started yet.
    pub fn new(count: u64) -> Stages {
        let bar = styled(
            ProgressBar::new(count),
            "[{pos}/{len}] {spinner} {msg} ({elapsed})",
        );
        bar.enable_steady_tick(std::time::Duration::from_millis(120));
        Stages { bar }
    }

    /// Starts the next stage, described by `what`.
    pub fn next(&self, what: String) {
        self.bar.inc(1);
        self.bar.set_message(what);
    }

    /// Prints a line to stderr without tearing the bar.
    pub fn note(&self, line: &str) {
        self.bar.suspend(|| eprintln!("{line}"));
    }
}

impl Drop for Stages {
    fn drop(&mut self) {
        self.bar.finish_and_clear();
    }
}

fn styled(bar: ProgressBar, template: &str) -> ProgressBar {
    bar.with_style(
        ProgressStyle::with_template(template).unwrap_or_else(|_| ProgressStyle::default_bar()),
    )
}
