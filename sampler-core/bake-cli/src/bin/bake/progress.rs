//! The progress bar every long bake shows.

use indicatif::{ProgressBar, ProgressStyle};

/// A bar of `total` steps labelled `what` (0: a spinner-like bar whose
/// length the bake sets later).
pub(crate) fn bar(total: u64, what: &str) -> ProgressBar {
    let pb = ProgressBar::new(total);
    pb.set_style(
        ProgressStyle::with_template("{msg:>12} [{elapsed_precise}] {wide_bar} {pos}/{len} ({eta})")
            .expect("static template is valid"),
    );
    pb.set_message(what.to_string());
    pb
}
