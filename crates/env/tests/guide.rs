//! The guide's in-process session (docs/rust.md, "Using the simulator in process"), run as
//! written there: `client/python/tests/test_docs_blocks.py` checks that the block's code is
//! this test's, line for line.

use gymfleet_env::{ActionType, EnvConfig, RobotEnv};

#[test]
fn the_guides_in_process_session_runs() -> Result<(), Box<dyn std::error::Error>> {
    // The guide's paths are the repository root's.
    std::env::set_current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))?;
    // docs/rust.md, from here:
    let doc = std::fs::read_to_string("models/pendulum.json")?;
    let mut env = RobotEnv::from_json(&doc, EnvConfig::with_end_effectors(["arm"]))?;
    let obs = env.reset(None); // [0], [0], [[10, 10, 25, 1, 0, 0, 0]]
    let result = env.step(ActionType::Torque, &[1e-4])?;
    println!("{:?} done={}", result.observation, result.flags.done());
    // to here.
    assert_eq!(obs.joint_positions, [0.0]);
    assert!(!result.flags.done());
    Ok(())
}
