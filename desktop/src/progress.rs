//! Progress on stderr for long runs, through `indicatif` (hidden when stderr is no terminal).

use indicatif::{ProgressBar, ProgressStyle};

/// A bar of `total` steps labelled `label`; `inc` it per step, `finish_and_clear` at the end.
pub fn bar(label: &str, total: u64) -> ProgressBar {
    let bar = ProgressBar::new(total);
    bar.set_style(
        ProgressStyle::with_template("{prefix} [{bar:30}] {pos}/{len} {msg} ({elapsed})")
            .expect("a valid template")
            .progress_chars("#> "),
    );
    bar.set_prefix(label.to_string());
    bar
}
