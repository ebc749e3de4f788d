//! SIGINT and SIGTERM: the process removes its temporaries, puts back any output folder
//! it had moved aside, and exits with 128 + the signal's number
//! ([`fem2rbd::output::interrupt`]).
use signal_hook::consts::{SIGINT, SIGTERM};
use signal_hook::iterator::Signals;

/// Installs the handler: a thread that waits for SIGINT or SIGTERM. Without it (the
/// handler cannot be installed) the signals keep their default action, and the next write
/// to the same place removes what a killed process left (`output::location`).
pub fn install() {
    let Ok(mut signals) = Signals::new([SIGINT, SIGTERM]) else {
        return;
    };
    let spawned = std::thread::Builder::new()
        .name("interrupt".into())
        .spawn(move || {
            if let Some(signal) = signals.forever().next() {
                let touched = fem2rbd::output::interrupt::clean_up();
                let name = if signal == SIGINT {
                    "SIGINT"
                } else {
                    "SIGTERM"
                };
                eprintln!(
                    "\ninterrupted ({name}): {} temporary output{} removed or put back; \
                     earlier outputs are as they were",
                    touched.len(),
                    if touched.len() == 1 { "" } else { "s" }
                );
                std::process::exit(128 + signal);
            }
        });
    drop(spawned);
}
