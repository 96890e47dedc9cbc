//! Converts an MJCF file into gymfleet's assembly JSON: the document on stdout, the
//! conversion's warnings on stderr.
//!
//! ```sh
//! cargo run -p gymfleet-import --example convert -- crates/import/tests/data/reacher.xml > reacher.json
//! ```

use std::process::ExitCode;

fn main() -> ExitCode {
    let Some(path) = std::env::args().nth(1) else {
        eprintln!("usage: convert FILE.xml");
        return ExitCode::from(2);
    };
    let text = match std::fs::read_to_string(&path) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("{path}: {e}");
            return ExitCode::FAILURE;
        }
    };
    match gymfleet_import::mjcf_to_document(&text) {
        Ok(converted) => {
            for warning in &converted.warnings {
                eprintln!("warning: {warning}");
            }
            println!("{:#}", converted.document);
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("{path}: {e}");
            ExitCode::FAILURE
        }
    }
}
