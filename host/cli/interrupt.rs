//! Ctrl-C and SIGTERM during a progressive render: the first finishes the current batch and
//! writes what there is; a second ends the process at once.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::OnceLock;

/// Raised by the first Ctrl-C or SIGTERM; a second one ends the process at once. None if the
/// handler could not be installed (then the signals keep their default effect).
pub fn interrupt_flag() -> Option<&'static AtomicBool> {
    static FLAG: AtomicBool = AtomicBool::new(false);
    static INSTALLED: OnceLock<bool> = OnceLock::new();
    let installed = *INSTALLED.get_or_init(|| {
        ctrlc::set_handler(|| {
            if FLAG.swap(true, Ordering::SeqCst) {
                // Second signal: the user wants out now. 130 = 128 + SIGINT.
                std::process::exit(130);
            }
            eprintln!("\ninterrupted: finishing the current batch, then writing the checkpoint and image");
        })
        .is_ok()
    });
    installed.then_some(&FLAG)
}
