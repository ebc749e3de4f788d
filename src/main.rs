//! The `fem2rbd` command: parse arguments, call the library, turn errors into one
//! clear message and a non-zero exit code.
use std::process::ExitCode;

fn main() -> ExitCode {
    match fem2rbd::cli::main() {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("error: {err:#}");
            ExitCode::FAILURE
        }
    }
}
