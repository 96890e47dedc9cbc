//! Saved states: a loaded state continues bitwise as its source does; a save leaves a
//! contact-free env's trajectory alone; bad bytes and states that do not fit are refused
//! with a precise error and change nothing.

mod common;

use common::{env_with, hand_and_post, hanging_pendulum, ARM2};
use gymfleet_env::{
    ActionType, EnvConfig, EnvError, Randomization, ReachTarget, RobotEnv, SavedState, TaskKind,
    TaskSpec, STATE_VERSION,
};
use serde_json::{json, Value};

/// A deterministic action sequence: torques that swing the arm through its range.
fn action(k: usize, dim: usize) -> Vec<f32> {
    (0..dim)
        .map(|j| 0.02 * ((k as f32) * 0.13 + j as f32 * 1.7).sin())
        .collect()
}

/// `steps` steps from `start`, every observation and flag as bits (resetting on done).
fn run(env: &mut RobotEnv, start: usize, steps: usize) -> Vec<u32> {
    let dim = env.spec().action_dim;
    let mut bits = Vec::new();
    for k in start..start + steps {
        let result = env
            .step(ActionType::Torque, &action(k, dim))
            .expect("valid action");
        bits.extend(result.observation.to_flat().iter().map(|v| v.to_bits()));
        bits.push(result.flags.reward.to_bits());
        bits.push(u32::from(result.flags.terminated) << 1 | u32::from(result.flags.truncated));
        if result.flags.done() {
            let obs = env.reset(None);
            bits.extend(obs.to_flat().iter().map(|v| v.to_bits()));
        }
    }
    bits
}

fn arm2() -> Value {
    serde_json::from_str(ARM2).expect("arm2 parses")
}

/// arm2 with everything a state must carry: a reach task with a drawn target, reset noise,
/// randomisation, and short episodes so that the runs cross resets (the generator's state).
fn busy_config() -> EnvConfig {
    EnvConfig {
        max_steps: 40,
        seed: 7,
        reset_noise: 5.0,
        task: Some(TaskSpec {
            kind: TaskKind::Reach {
                end_effector: "forearm".into(),
                point: None,
                target: ReachTarget::Box {
                    min: [-100.0, -100.0, 0.0],
                    max: [100.0, 100.0, 100.0],
                },
                success_radius: 0.0,
                terminate_on_success: false,
            },
            action_cost: 0.1,
        }),
        randomize: Some(Randomization {
            mass_scale: Some([0.8, 1.2]),
            friction_scale: None,
            damping_scale: Some([0.5, 2.0]),
            gain_scale: None,
        }),
        ..EnvConfig::with_end_effectors(["forearm"])
    }
}

/// Steps `env` 25 steps, saves, and checks that an env loaded from the bytes, the saved
/// env itself and a copy of it that was never saved give the same bits for `steps` more
/// steps (the last because `env` has no contacts: a save then changes nothing).
fn assert_exact(mut env: RobotEnv, steps: usize) {
    let mut never_saved = env.clone();
    run(&mut never_saved, 0, 25);
    run(&mut env, 0, 25);
    let bytes = env.save().expect("a healthy env saves").encode();
    let state = SavedState::decode(&bytes).expect("its own bytes decode");
    let mut loaded = RobotEnv::from_state(&state).expect("its own state loads");
    assert_eq!(loaded.elapsed_steps(), env.elapsed_steps());
    assert_eq!(
        loaded.observe().to_flat(),
        env.observe().to_flat(),
        "same observation on load"
    );
    let mut twin = RobotEnv::from_state(&state).expect("loads twice");
    let original = run(&mut env, 25, steps);
    assert_eq!(
        run(&mut loaded, 25, steps),
        original,
        "loaded env diverged from its source"
    );
    assert_eq!(
        run(&mut twin, 25, steps),
        original,
        "second loaded env diverged"
    );
    assert_eq!(
        run(&mut never_saved, 25, steps),
        original,
        "the save changed the trajectory"
    );
}

#[test]
fn a_loaded_state_continues_bitwise_like_its_source() {
    assert_exact(env_with(&arm2(), busy_config()), 200);
}

#[test]
fn a_loaded_state_with_contacts_continues_bitwise_and_the_save_barely_perturbs() {
    // The hand is driven onto the post and rests against it when the state is saved.
    let mut env = env_with(&hand_and_post(), EnvConfig::with_end_effectors(["hand"]));
    for _ in 0..60 {
        env.step(ActionType::Torque, &[2e-3]).expect("valid");
    }
    let mut never_saved = env.clone();
    let mut loaded = RobotEnv::from_state(&env.save().expect("saves")).expect("loads");
    let mut differs = 0.0f32;
    for k in 0..120 {
        let torque = [if k < 60 { 2e-3 } else { -1e-3 }];
        let a = env.step(ActionType::Torque, &torque).expect("valid");
        let b = loaded.step(ActionType::Torque, &torque).expect("valid");
        let c = never_saved
            .step(ActionType::Torque, &torque)
            .expect("valid");
        assert_eq!(
            a.observation.to_flat(),
            b.observation.to_flat(),
            "step {k} after the load"
        );
        let (a, c) = (a.observation.to_flat(), c.observation.to_flat());
        differs = differs.max((a[0] - c[0]).abs());
    }
    // Saving re-seats the env: the resting contact is solved afresh, without last step's
    // impulses as a first guess. The hand then sits up to 0.009° deeper against the post for
    // a few dozen steps (measured); bound it well below the contact tests' tolerances.
    assert!(
        differs < 0.05,
        "a save moved the resting hand by {differs}° against an env never saved"
    );
}

#[test]
fn a_ball_joint_state_continues_bitwise() {
    let doc = hanging_pendulum(json!({"type": "ball"}));
    let mut env = env_with(&doc, EnvConfig::with_end_effectors(["arm"]));
    // Tip it, so that its rotation is not about one axis.
    for k in 0..30 {
        env.step(
            ActionType::Torque,
            &[1e-3, -2e-3 * (k as f32 * 0.1).cos(), 5e-4],
        )
        .expect("valid");
    }
    assert_exact(env, 100);
}

#[test]
fn saving_a_contact_free_env_does_not_change_its_trajectory() {
    let mut saved = env_with(&arm2(), busy_config());
    let mut untouched = env_with(&arm2(), busy_config());
    let before = run(&mut saved, 0, 25);
    assert_eq!(run(&mut untouched, 0, 25), before);
    saved.save().expect("saves");
    assert_eq!(run(&mut saved, 25, 200), run(&mut untouched, 25, 200));
}

#[test]
fn a_state_loads_into_an_env_of_the_same_document_and_options() {
    let mut source = env_with(&arm2(), busy_config());
    run(&mut source, 0, 30);
    let state = source.save().expect("saves");
    // Another creation seed is fine: the state carries its episode's seed and generator.
    let mut target = env_with(
        &arm2(),
        EnvConfig {
            seed: 99,
            ..busy_config()
        },
    );
    target.load(&state).expect("same document and options");
    assert_eq!(target.seed(), source.seed());
    assert_eq!(run(&mut target, 30, 100), run(&mut source, 30, 100));
}

#[test]
fn a_state_of_another_env_is_refused_and_changes_nothing() {
    let mut source = env_with(&arm2(), busy_config());
    run(&mut source, 0, 10);
    let state = source.save().expect("saves");

    let mut other_doc = env_with(
        &hanging_pendulum(json!({})),
        EnvConfig::with_end_effectors(["arm"]),
    );
    let before = other_doc.observe().to_flat();
    let err = other_doc.load(&state).expect_err("another document");
    assert_eq!(
        err.to_string(),
        "state.document: the state was saved from an env of another document"
    );
    assert_eq!(other_doc.observe().to_flat(), before, "nothing changed");

    let mut other_substeps = env_with(
        &arm2(),
        EnvConfig {
            substeps: 8,
            ..busy_config()
        },
    );
    let err = other_substeps.load(&state).expect_err("other substeps");
    assert_eq!(
        err.to_string(),
        "state.config.substeps: the state was saved from an env with another substeps"
    );
    let mut no_task = env_with(
        &arm2(),
        EnvConfig {
            task: None,
            ..busy_config()
        },
    );
    let err = no_task.load(&state).expect_err("no task");
    assert_eq!(
        err.to_string(),
        "state.config.task: the state was saved from an env with another task"
    );
}

#[test]
fn bad_bytes_get_precise_errors() {
    let mut env = env_with(&arm2(), busy_config());
    run(&mut env, 0, 5);
    let bytes = env.save().expect("saves").encode();
    let message = |b: &[u8]| match SavedState::decode(b) {
        Err(e @ EnvError::StateFormat { .. }) => e.to_string(),
        other => panic!("expected a format error, got {other:?}"),
    };

    assert_eq!(
        message(&[]),
        "state: 0 bytes is shorter than a state's 12-byte header (empty or truncated)"
    );
    assert_eq!(
        message(b"{\"parts\": [], \"assembly\": {}}"),
        "state: not a gymfleet env state: it starts with [7b, 22, 70, 61], not \"GFST\""
    );
    let mut other_version = bytes.clone();
    other_version[4..8].copy_from_slice(&(STATE_VERSION + 1).to_le_bytes());
    assert_eq!(
        message(&other_version),
        format!(
            "state: the state has format version {}; this server reads version {STATE_VERSION} only",
            STATE_VERSION + 1
        )
    );
    // Every truncation and every single flipped bit is caught by the checksum (or the
    // header), never a panic.
    for len in 0..bytes.len() {
        let m = message(&bytes[..len]);
        assert!(m.starts_with("state: "), "{len} bytes: {m}");
    }
    for at in (0..bytes.len()).step_by(7) {
        let mut flipped = bytes.clone();
        flipped[at] ^= 0x10;
        let m = message(&flipped);
        assert!(
            m.contains("checksum mismatch") || m.contains("GFST") || m.contains("version"),
            "byte {at}: {m}"
        );
    }
    // A forged length prefix (a 34-gigabyte document in a 17-byte state) is an encoding
    // error, not an allocation of that size.
    let payload = [0xff, 0xff, 0xff, 0xff, 0x7f];
    let mut huge = b"GFST".to_vec();
    huge.extend_from_slice(&STATE_VERSION.to_le_bytes());
    huge.extend_from_slice(&crc32fast::hash(&payload).to_le_bytes());
    huge.extend_from_slice(&payload);
    assert!(
        message(&huge).starts_with("state: malformed state fields: "),
        "{}",
        message(&huge)
    );
    let mut longer = bytes.clone();
    longer.push(0);
    assert!(message(&longer).contains("checksum mismatch"));
}

#[test]
fn a_diverged_env_cannot_be_saved() {
    let doc = hanging_pendulum(json!({}));
    let mut env = env_with(&doc, EnvConfig::with_end_effectors(["arm"]));
    // 1e35 N·m blows the pendulum up in one step (as the divergence test in semantics.rs).
    let flags = env.step(ActionType::Torque, &[1e35]).expect("valid").flags;
    assert!(flags.terminated, "the step diverged");
    assert_eq!(env.save().expect_err("diverged"), EnvError::NeedsReset);
    env.reset(None);
    env.save().expect("a reset env saves");
}

/// A state's payload (after the header) with `edits` applied and the checksum made valid
/// again: what a deliberate forger can send.
/// An edit at `at` counts from the end when `from_end` (the episode and physics fields
/// follow the document).
fn forge(bytes: &[u8], edits: &[(bool, usize, u8)], cut: usize) -> Vec<u8> {
    let mut payload = bytes[12..].to_vec();
    let len = payload.len();
    for &(from_end, at, value) in edits {
        let at = if from_end {
            len - 1 - at % 400.min(len)
        } else {
            at % len
        };
        payload[at] = value;
    }
    payload.truncate(payload.len() - cut.min(payload.len()));
    let mut out = bytes[..8].to_vec();
    out.extend_from_slice(&crc32fast::hash(&payload).to_le_bytes());
    out.extend_from_slice(&payload);
    out
}

proptest::proptest! {
    #![proptest_config(proptest::test_runner::Config { cases: 400, ..Default::default() })]

    /// Forged bytes with a valid checksum: decoding, loading, building from the state and
    /// stepping the result never panic; every refusal is a state or document error.
    #[test]
    fn forged_states_never_panic(
        edits in proptest::collection::vec(
            (proptest::bool::weighted(0.8), 0usize..4096, proptest::num::u8::ANY),
            1..4,
        ),
        cut in proptest::prop_oneof![
            4 => proptest::strategy::Just(0usize),
            1 => 0usize..64,
        ],
    ) {
        let mut env = env_with(&arm2(), busy_config());
        run(&mut env, 0, 5);
        let bytes = env.save().expect("saves").encode();
        let forged = forge(&bytes, &edits, cut);
        let Ok(state) = SavedState::decode(&forged) else { return Ok(()) };
        match env.load(&state) {
            Ok(()) => { run(&mut env, 5, 5); }
            Err(err) => proptest::prop_assert!(
                err.to_string().starts_with("state") || matches!(err, EnvError::Document(_)),
                "{err}"
            ),
        }
        if let Ok(mut built) = RobotEnv::from_state(&state) {
            let dim = built.spec().action_dim;
            for k in 0..5 {
                let _ = built.step(ActionType::Torque, &action(k, dim));
            }
        }
    }
}
