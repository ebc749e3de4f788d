//! The `fem2rbd` command: parse arguments, call the library, turn errors into one
//! clear message and a non-zero exit code.
#![forbid(unsafe_code)]
use std::process::ExitCode;

mod cli;

fn main() -> ExitCode {
    match cli::main() {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("error: {err:#}");
            ExitCode::FAILURE
        }
    }
}
