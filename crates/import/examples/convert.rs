//! Converts a URDF or MJCF file into gymfleet's assembly JSON: the document on stdout, the
//! conversion's warnings on stderr. Meshes are read from the file's folder or the folders
//! above it; a second argument names the folder (or a zip/tar) that holds them instead
//! (`package://` and relative paths resolve against it).
//!
//! ```sh
//! cargo run -p gymfleet-import --example convert -- crates/import/tests/data/reacher.xml > reacher.json
//! cargo run -p gymfleet-import --example convert -- \
//!     crates/import/tests/data/example-robot-data/robots/ur_description/urdf/ur5_robot.urdf \
//!     crates/import/tests/data > ur5.json
//! ```

use std::path::Path;
use std::process::ExitCode;

use gymfleet_import::Assets;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(path) = args.first() else {
        eprintln!("usage: convert FILE.xml|FILE.urdf [ASSETS_DIR|ASSETS.zip|ASSETS.tar]");
        return ExitCode::from(2);
    };
    let result = match args.get(1).map(Path::new) {
        None => gymfleet_import::convert_file(Path::new(path)).map_err(|e| e.to_string()),
        Some(root) => std::fs::read_to_string(path)
            .map_err(|e| e.to_string())
            .and_then(|text| {
                let assets = if root.is_dir() {
                    Assets::from_dir(root)
                } else {
                    let bytes =
                        std::fs::read(root).map_err(|e| format!("{}: {e}", root.display()))?;
                    Assets::from_archive(&bytes)
                }
                .map_err(|e| e.to_string())?;
                gymfleet_import::convert(&text, None, Some(&assets))
                    .map(|c| (c.json, c.warnings))
                    .map_err(|e| e.to_string())
            }),
    };
    match result {
        Ok((document, warnings)) => {
            for warning in &warnings {
                eprintln!("warning: {warning}");
            }
            match serde_json::from_str::<serde_json::Value>(&document) {
                Ok(v) => println!("{v:#}"),
                Err(_) => println!("{document}"),
            }
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("{path}: {e}");
            ExitCode::FAILURE
        }
    }
}
