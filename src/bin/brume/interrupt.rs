//! Ctrl-C, SIGTERM and SIGHUP: brume answers every stop request within a
//! second, with exit code 130.
//!
//! While nothing is being rendered (loading a scene or a frame's volumes,
//! hashing inputs, merge, compare, info) there is nothing to save: a request
//! removes the temporary file of any write under way and exits at once.
//! While a render runs ([`saving`] on), the first request only sets the
//! stop flag: the render drops the pass under way, its finished passes are
//! written, and brume exits with 130. A second request exits at once.

use brume::film::image_io;
use std::sync::atomic::{AtomicBool, Ordering};

/// Exit code of a run stopped by a signal (128 + SIGINT, as shells report an interrupted command).
pub const EXIT_INTERRUPTED: i32 = 130;

/// Set by the first stop request.
static STOP: AtomicBool = AtomicBool::new(false);
/// On while a render has finished passes to save (or will have).
static SAVING: AtomicBool = AtomicBool::new(false);

/// Installs the handler; called once, first thing in `main`.
pub fn install() {
    let installed = ctrlc::set_handler(|| {
        let again = STOP.swap(true, Ordering::SeqCst);
        if again || !SAVING.load(Ordering::SeqCst) {
            image_io::discard_temporaries();
            if !again {
                eprintln!("interrupted: stopped before rendering; files written earlier stay as they were");
            }
            std::process::exit(EXIT_INTERRUPTED);
        }
    });
    if let Err(e) = installed {
        eprintln!(
            "warning: cannot catch Ctrl-C ({e}); a stop request will end brume without saving"
        );
    }
}

/// The stop flag the render reads before every sample.
pub fn flag() -> &'static AtomicBool {
    &STOP
}

/// True once a stop was requested.
pub fn requested() -> bool {
    STOP.load(Ordering::SeqCst)
}

/// Turns saving mode on (a render is about to run: stop requests set the
/// flag) or off (stop requests exit at once).
pub fn saving(on: bool) {
    SAVING.store(on, Ordering::SeqCst);
}
