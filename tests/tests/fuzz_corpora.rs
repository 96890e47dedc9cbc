//! The fuzz corpora (`fuzz/corpus/<target>/`, issue R2) replayed through the fuzz targets'
//! own bodies (`fuzz/src/targets.rs`) as an ordinary test: a regression on a known input is
//! caught without a fuzzing build. Prints how far the inputs of each corpus got.

#[path = "../../fuzz/src/targets.rs"]
#[allow(dead_code, unreachable_pub)]
mod targets;

use std::collections::BTreeMap;
use std::path::Path;

use targets::Reached;

/// Replays `fuzz/corpus/<target>/` (or `$GYMFLEET_FUZZ_CORPORA/<target>/`, e.g. a fuzzing
/// run's working corpus, to measure how far its inputs get).
fn replay(target: &str, run: fn(&[u8]) -> Reached) {
    let root = std::env::var_os("GYMFLEET_FUZZ_CORPORA").map_or_else(
        || Path::new(env!("CARGO_MANIFEST_DIR")).join("../fuzz/corpus"),
        std::path::PathBuf::from,
    );
    let dir = root.join(target);
    let mut reached: BTreeMap<Reached, usize> = BTreeMap::new();
    let mut paths: Vec<_> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.expect("entry").path())
        .collect();
    paths.sort();
    for path in &paths {
        let data = std::fs::read(path).expect("read");
        let got = std::panic::catch_unwind(|| run(&data))
            .unwrap_or_else(|_| panic!("{target}: {} failed", path.display()));
        *reached.entry(got).or_default() += 1;
    }
    println!("{target}: {} inputs, reached {reached:?}", paths.len());
    assert!(!paths.is_empty(), "{target}: an empty corpus");
}

#[test]
fn the_assembly_document_corpus_replays() {
    replay("assembly_document", targets::assembly_document);
}

#[test]
fn the_mjcf_corpus_replays() {
    replay("mjcf", targets::mjcf);
}

#[test]
fn the_urdf_corpus_replays() {
    replay("urdf", targets::urdf);
}

#[test]
fn the_saved_state_corpus_replays() {
    replay("saved_state", targets::saved_state);
}

/// Writes the saved-state seeds (each model's env after a few driven steps) when
/// `GYMFLEET_WRITE_STATE_SEEDS` is set; a no-op otherwise.
#[test]
fn write_saved_state_seeds() {
    if std::env::var_os("GYMFLEET_WRITE_STATE_SEEDS").is_none() {
        return;
    }
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fuzz/corpus/saved_state");
    let models = Path::new(env!("CARGO_MANIFEST_DIR")).join("../models");
    for entry in std::fs::read_dir(models).expect("models") {
        let path = entry.expect("entry").path();
        let text = std::fs::read_to_string(&path).expect("read");
        let mut env = gymfleet_env::RobotEnv::from_json(&text, gymfleet_env::EnvConfig::default())
            .expect("env");
        let ones = vec![1e-3f32; env.spec().action_dim];
        for _ in 0..10 {
            env.step(gymfleet_env::ActionType::Torque, &ones)
                .expect("step");
        }
        let bytes = env.save().expect("save").encode();
        let name = path
            .file_stem()
            .expect("stem")
            .to_string_lossy()
            .to_string();
        std::fs::write(dir.join(format!("{name}.state")), bytes).expect("write");
    }
}
