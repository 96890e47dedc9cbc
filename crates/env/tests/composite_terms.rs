//! The terms the Control Suite's rewards are made of, on a hanging pendulum: a frame's
//! axis (MuJoCo's `xmat`), an action value, dm_control's `tolerance` of an earlier term,
//! sums and products of terms; and the starts its tasks draw (every limited joint in its
//! range, every unlimited hinge in [−π, π], normal draws, settling steps).

mod common;

use common::env_with;
use gymfleet_env::{ActionType, EnvConfig, RobotEnv, TaskKind, TaskSpec, TermsTask, Units};
use serde_json::{json, Value};

fn pendulum(extra: Value) -> Value {
    let mut joint = json!({"name": "hinge"});
    common::merge(&mut joint, extra);
    common::hanging_pendulum(joint)
}

fn env(doc: &Value, task: Value) -> RobotEnv {
    let config = EnvConfig {
        units: Units::Si,
        task: Some(TaskSpec {
            kind: TaskKind::Terms(TermsTask::from_json(&task.to_string()).expect("a terms task")),
            action_cost: 0.0,
        }),
        ..EnvConfig::default()
    };
    env_with(doc, config)
}

fn refused(task: Value) -> String {
    let config = EnvConfig {
        units: Units::Si,
        ..EnvConfig::default()
    };
    common::with_terms(&pendulum(json!({})).to_string(), &task.to_string(), config)
        .err()
        .expect("refused")
        .to_string()
}

/// At angle θ about +Y the arm's z axis is (sin θ, 0, cos θ): `xmat[zz]` = cos θ and
/// `xmat[xz]` = sin θ, read at the reset (observed) and after a step.
#[test]
fn a_frames_axis_reads_as_mujocos_xmat() {
    let theta = 0.5_f64;
    let task = json!({
        "terms": [
            {"name": "zz", "weight": 0, "observe": true,
             "value": {"instance": "arm", "axis": "z", "frame_axis": "z"}},
            {"name": "xz", "weight": 0, "observe": true,
             "value": {"instance": "arm", "axis": "x", "frame_axis": "z"}},
            {"name": "yy", "weight": 0, "observe": true,
             "value": {"instance": "arm", "axis": "y", "frame_axis": "y"}}
        ],
        "reset_noise": {"set": [{"joints": ["hinge"], "low": [theta], "high": [theta]}]}
    });
    let mut e = env(&pendulum(json!({})), task);
    let obs = e.reset(Some(0));
    let angle = f64::from(obs.joint_positions[0]);
    assert!((angle - theta).abs() < 1e-6, "{angle}");
    let [zz, xz, yy] = [obs.task[0], obs.task[1], obs.task[2]].map(f64::from);
    assert!((zz - angle.cos()).abs() < 1e-6, "zz {zz}");
    assert!((xz.abs() - angle.sin()).abs() < 1e-6, "xz {xz}");
    assert!((yy - 1.0).abs() < 1e-6, "yy {yy}");
    let r = e.step(ActionType::Torque, &[0.0]).expect("steps");
    let angle = f64::from(r.observation.joint_positions[0]);
    let zz = f64::from(e.term_values()[0]);
    assert!((zz - angle.cos()).abs() < 1e-5, "{zz} at {angle}");
}

/// `tolerance`, `sum` and `product` of earlier terms, and the action's value: the
/// reward is the weighted `product` term only.
#[test]
fn tolerance_sums_and_products_combine_earlier_terms() {
    let task = json!({"terms": [
        {"name": "u", "weight": 0, "value": {"action": 0}},
        {"name": "small", "weight": 0,
         "tolerance": {"of": "u", "margin": 1.0, "sigmoid": "quadratic", "value_at_margin": 0.0}},
        {"name": "inside", "weight": 0, "tolerance": {"of": "u", "bounds": [null, 0.25]}},
        {"name": "mixed", "weight": 0,
         "sum": [{"term": "small", "scale": 0.2, "offset": 0.8}, {"term": "inside", "scale": 0.5}]},
        {"name": "reward", "weight": 2,
         "product": [{"term": "mixed"}, {"term": "small", "scale": -1, "offset": 1}]}
    ]});
    let mut e = env(&pendulum(json!({})), task);
    e.reset(Some(0));
    for u in [0.0_f64, 0.2, 0.5, -0.5, 1.5] {
        let r = e.step(ActionType::Torque, &[u as f32]).expect("steps");
        let v: Vec<f64> = e.term_values().iter().map(|&x| f64::from(x)).collect();
        let u = f64::from(u as f32);
        let small = if u.abs() < 1.0 { 1.0 - u * u } else { 0.0 };
        let inside = if u <= 0.25 { 1.0 } else { 0.0 };
        let mixed = 0.2 * small + 0.8 + 0.5 * inside;
        let want = mixed * (1.0 - small);
        assert!((v[0] - u).abs() < 1e-7);
        assert!((v[1] - small).abs() < 1e-6, "{u}: small {}", v[1]);
        assert_eq!(v[2], inside);
        assert!((v[3] - mixed).abs() < 1e-6);
        assert!((v[4] - want).abs() < 1e-6);
        assert!((f64::from(r.flags.reward) - 2.0 * want).abs() < 1e-6);
    }
}

#[test]
fn composite_terms_refuse_bad_references_with_their_path() {
    for (task, expected) in [
        (
            json!({"terms": [{"name": "t", "tolerance": {"of": "later"}},
                             {"name": "later", "value": {"joint": "hinge"}}]}),
            "task.terms.terms[0].tolerance.of: \"later\" is not an earlier term (a term reads only the terms listed before it)",
        ),
        (
            json!({"terms": [{"name": "a", "value": {"joint": "hinge"}},
                             {"name": "p", "product": [{"term": "a"}, {"term": "p"}]}]}),
            "task.terms.terms[1].product[1].term: \"p\" is not an earlier term (a term reads only the terms listed before it: \"a\")",
        ),
        (
            json!({"terms": [{"name": "s", "sum": []}]}),
            "task.terms.terms[0].sum: expected 1 to 512 factors, got 0",
        ),
        (
            json!({"terms": [{"name": "a", "value": {"action": 1}}]}),
            "task.terms.terms[0].value.action: expected an action index below the action's length (1), got 1",
        ),
        (
            json!({"terms": [{"name": "a", "value": {"joint": "hinge", "frame_axis": "z"}}]}),
            "task.terms.terms[0].value.frame_axis: a frame axis belongs to an instance or a site",
        ),
        (
            json!({"terms": [{"name": "a", "value": {"instance": "arm", "frame_axis": "z"}}]}),
            "task.terms.terms[0].value.axis: a point's coordinate needs an axis",
        ),
        (
            json!({"terms": [], "reset_noise": {"set": [
                {"joints": ["hinge"], "mean": [0.0], "std": [-1.0]}]}}),
            "task.terms.reset_noise.set[0].std[0]: expected a standard deviation >= 0, got -1",
        ),
        (
            json!({"terms": [], "reset_noise": {"set": [
                {"joints": ["hinge"], "mean": [0.0, 1.0], "std": [0.1]}]}}),
            "task.terms.reset_noise.set[0]: expected one mean and one std per joint (1), got 2 and 1",
        ),
        (
            json!({"terms": [], "reset_noise": {"set": [
                {"joints": ["hinge"], "mean": [0.0], "std": [0.1], "max_norm": 1.0}]}}),
            "task.terms.reset_noise.set[0]: a normal draw (mean, std) takes no min_norm or max_norm",
        ),
        (
            json!({"terms": [{"name": "a", "value":
                {"instance": "arm", "axis": "z", "frame_axis": "z", "relative_to": "x"}}]}),
            "task.terms.terms[0].value.relative_to: a frame axis is read in the world: it takes no relative_to",
        ),
        (
            json!({"terms": [{"name": "a", "value":
                {"instance": "arm", "axis": "z", "frame_axis": "z", "point": [0, 0, 0]}}]}),
            "task.terms.terms[0].value.point: a frame axis is the frame's own: it takes no point",
        ),
        (
            json!({"terms": [{"name": "a", "value":
                {"body_center": ["arm"], "axis": "z", "point": [0, 0, 0]}}]}),
            "task.terms.terms[0].value.point: a body's centre of mass takes no point",
        ),
        (
            json!({"terms": [{"name": "a", "value": {"joint": "hinge"}},
                             {"name": "t", "tolerance": {"of": "a", "bounds": [null, null], "margin": 1.0, "value_at_margin": 1.0}}]}),
            "task.terms.terms[1].tolerance.value_at_margin: expected 0 < value_at_margin < 1 (the Gaussian sigmoid), got 1",
        ),
        (
            json!({"terms": [], "reset_noise": {"set": [
                {"joints": ["hinge"], "mean": [0.0], "low": [0.0], "high": [1.0]}]}}),
            "task.terms.reset_noise.set[0]: expected either low and high (a uniform box) or mean and std (normal draws)",
        ),
    ] {
        let err = refused(task);
        assert!(err.contains(expected), "{err}\n  expected: {expected}");
    }
}

/// dm_control's `randomize_limited_and_rotational_joints`: a limited hinge uniform in its
/// range, an unlimited one in [−π, π]; a normal set around its mean; a velocity noise kept
/// on a set joint that is not `at_rest`.
#[test]
fn the_suites_starts_are_drawn_in_ranges_and_around_means() {
    let draws = |doc: &Value, noise: Value, n: usize| -> Vec<(f64, f64)> {
        let mut e = env(doc, json!({"terms": [], "reset_noise": noise}));
        (0..n)
            .map(|k| {
                let o = e.reset(Some(k as u64));
                (
                    f64::from(o.joint_positions[0]),
                    f64::from(o.joint_velocities[0]),
                )
            })
            .collect()
    };
    let limited = pendulum(json!({"min": -30, "max": 60}));
    let q: Vec<f64> = draws(&limited, json!({"limited": true}), 200)
        .iter()
        .map(|d| d.0)
        .collect();
    let (lo, hi) = (-30f64.to_radians(), 60f64.to_radians());
    assert!(q.iter().all(|&x| x >= lo - 1e-6 && x <= hi + 1e-6));
    assert!(q.iter().any(|&x| x < lo + 0.1) && q.iter().any(|&x| x > hi - 0.1));
    // `rotational` leaves a limited joint alone, and `limited` an unlimited one.
    assert!(draws(&limited, json!({"rotational": true}), 5)
        .iter()
        .all(|d| d.0 == 0.0));
    let free = pendulum(json!({}));
    assert!(draws(&free, json!({"limited": true}), 5)
        .iter()
        .all(|d| d.0 == 0.0));
    let q: Vec<f64> = draws(&free, json!({"rotational": true}), 200)
        .iter()
        .map(|d| d.0)
        .collect();
    let pi = std::f64::consts::PI;
    assert!(q.iter().all(|&x| x.abs() <= pi + 1e-6));
    assert!(q.iter().any(|&x| x < -2.8) && q.iter().any(|&x| x > 2.8));
    let normal = json!({"set": [{"joints": ["hinge"], "mean": [3.0], "std": [0.01], "at_rest": false}],
                        "velocity": {"normal": 0.01}});
    let d = draws(&free, normal, 400);
    let mean = d.iter().map(|x| x.0).sum::<f64>() / d.len() as f64;
    let sd = (d.iter().map(|x| (x.0 - mean).powi(2)).sum::<f64>() / d.len() as f64).sqrt();
    let vsd = (d.iter().map(|x| x.1 * x.1).sum::<f64>() / d.len() as f64).sqrt();
    assert!(
        (mean - 3.0).abs() < 0.003 && (sd - 0.01).abs() < 0.002,
        "{mean} {sd}"
    );
    assert!((vsd - 0.01).abs() < 0.002, "velocity noise kept: {vsd}");
    let rest = json!({"set": [{"joints": ["hinge"], "mean": [3.0], "std": [0.01]}],
                      "velocity": {"normal": 0.01}});
    assert!(draws(&free, rest, 5).iter().all(|x| x.1 == 0.0));
}

/// Settling: the pendulum released at 90° swings for the settling steps before the
/// episode's first observation; the episode's step count starts after them.
#[test]
fn settling_steps_run_before_the_first_observation() {
    let start = std::f64::consts::FRAC_PI_2;
    let noise = |settle: u32| {
        json!({"terms": [], "reset_noise": {
            "set": [{"joints": ["hinge"], "low": [start], "high": [start]}],
            "settle_substeps": settle}})
    };
    let doc = pendulum(json!({}));
    let mut still = env(&doc, noise(0));
    // Ten whole steps of substeps (a part of a step rounds up to a whole one).
    let substeps = EnvConfig::default().substeps;
    let mut settled = env(&doc, noise(10 * substeps - 1));
    let o = still.reset(Some(0));
    assert!((f64::from(o.joint_positions[0]) - start).abs() < 1e-6);
    let mut after = Vec::new();
    for _ in 0..10 {
        after = still
            .step(ActionType::Torque, &[0.0])
            .expect("steps")
            .observation
            .joint_positions;
    }
    let o = settled.reset(Some(0));
    assert_eq!(o.joint_positions, after, "ten steps of zero action");
    assert_eq!(settled.elapsed_steps(), 0);
}

/// A point's offset in a site's frame (`relative_to`) is the same local vector at every
/// angle; `norm` is a vector's length.
#[test]
fn offsets_in_a_sites_frame_and_norms() {
    let mut doc = pendulum(json!({}));
    doc["assembly"]["sites"] =
        json!([{"name": "corner", "instance": "arm", "point": {"x": 0, "y": 0, "z": 0}}]);
    let task = |theta: f64| {
        json!({"terms": [
            {"name": "x", "weight": 0, "value": {"instance": "arm", "relative_to": "corner", "axis": "x"}},
            {"name": "z", "weight": 0, "value": {"instance": "arm", "relative_to": "corner", "axis": "z"}},
            {"name": "u", "weight": 0, "value": {"action": 0}},
            {"name": "n", "weight": 0, "norm": [{"term": "u", "offset": 3}, {"term": "u", "scale": 0, "offset": 4}]}
        ], "reset_noise": {"set": [{"joints": ["hinge"], "low": [theta], "high": [theta]}]}})
    };
    for theta in [0.0, 0.7, -2.0] {
        let mut e = env(&doc, task(theta));
        e.reset(Some(0));
        e.step(ActionType::Torque, &[0.0]).expect("steps");
        let v = e.term_values();
        // The arm's centre of mass is (2, 2, 20) mm from its frame's corner.
        assert!((f64::from(v[0]) - 0.002).abs() < 1e-6, "{theta}: {}", v[0]);
        assert!((f64::from(v[1]) - 0.020).abs() < 1e-6, "{theta}: {}", v[1]);
        assert!((f64::from(v[3]) - 5.0).abs() < 1e-6);
    }
    let err = refused(json!({"terms": [{"name": "a", "value":
        {"center_of_mass": true, "relative_to": "corner", "axis": "x"}}]}));
    assert!(
        err.contains("value.relative_to: an offset from a site belongs to a site, or an instance"),
        "{err}"
    );
}

/// `reject_contacts`: starts where the arm overlaps a block below it are drawn again.
#[test]
fn starts_in_contact_are_drawn_again() {
    let mut doc = pendulum(json!({}));
    doc["parts"].as_array_mut().expect("parts").push(
        json!({"name": "Block", "primitive": {"type": "cube", "size": {"x": 60, "y": 20, "z": 5}}}),
    );
    doc["assembly"]["instances"]
        .as_array_mut()
        .expect("instances")
        .push(json!({"part": "Block", "name": "block", "position": {"x": -20, "y": 0, "z": -35}}));
    doc["assembly"]["joints"]
        .as_array_mut()
        .expect("joints")
        .push(json!({"type": "fixed", "parent": "base", "child": "block", "anchor": {"x": 0, "y": 10, "z": -30}}));
    let cosines = |reject: bool| -> Vec<f64> {
        let mut e = env(
            &doc,
            json!({"terms": [], "reset_noise": {"rotational": true, "reject_contacts": reject}}),
        );
        (0..200)
            .map(|k| f64::from(e.reset(Some(k)).joint_positions[0]).cos())
            .collect()
    };
    // Hanging within ~40° of straight down, the 40 mm arm reaches below the block's top
    // (30 mm down).
    assert!(cosines(false).iter().any(|&c| c > 0.9));
    assert!(cosines(true).iter().all(|&c| c < 0.8));
}

/// `reset_noise.mocap`: a target mocap body starts on an arc, or in one of two weighted
/// boxes, every episode; a distance term reads it there.
#[test]
fn mocap_targets_start_where_they_are_drawn() {
    let mut doc = pendulum(json!({}));
    doc["parts"]
        .as_array_mut()
        .expect("parts")
        .push(json!({"name": "Mark", "primitive": {"type": "sphere", "radius": 5}}));
    doc["assembly"]["instances"]
        .as_array_mut()
        .expect("instances")
        .push(
            json!({"part": "Mark", "name": "target", "position": {"x": 0, "y": 0, "z": 500},
                     "mocap": true, "collision": {"group": 0, "mask": 0}}),
        );
    let place = |draw: Value| {
        let mut e = env(
            &doc,
            json!({"terms": [
                {"name": "x", "weight": 0, "value": {"instance": "target", "axis": "x"}},
                {"name": "y", "weight": 0, "value": {"instance": "target", "axis": "y"}},
                {"name": "z", "weight": 0, "value": {"instance": "target", "axis": "z"}}
            ], "reset_noise": {"mocap": [draw]}}),
        );
        (0..300)
            .map(|k| {
                e.reset(Some(k));
                e.step(ActionType::Torque, &[0.0]).expect("steps");
                let v = e.term_values();
                [v[0], v[1], v[2]].map(f64::from)
            })
            .collect::<Vec<_>>()
    };
    let arc = place(
        json!({"body": "target", "polar": {"plane": "xy", "center": [0.0, 0.0, 0.5],
                                                      "radius": [0.05, 0.2], "angle": [0.0, std::f64::consts::TAU]}}),
    );
    for p in &arc {
        let r = p[0].hypot(p[1]);
        assert!((0.05 - 1e-5..=0.2 + 1e-5).contains(&r), "{p:?}");
        assert!((p[2] - 0.5).abs() < 1e-5);
    }
    assert!(arc.iter().any(|p| p[0] < -0.1) && arc.iter().any(|p| p[1] > 0.1));
    let boxes = place(json!({"body": "target", "boxes": [
        {"weight": 0.2, "low": [-0.3, -0.3, 0.0], "high": [0.3, 0.3, 0.0]},
        {"weight": 0.8, "low": [-2.0, -2.0, 0.0], "high": [2.0, 2.0, 0.0]}]}));
    let near = boxes
        .iter()
        .filter(|p| p[0].abs() <= 0.3 && p[1].abs() <= 0.3)
        .count();
    // 0.2 + 0.8 · (0.6 / 4)² of the draws: 21.8 %.
    assert!((40..=95).contains(&near), "{near} of 300 near");
    assert!(boxes
        .iter()
        .all(|p| p[0].abs() <= 2.0 + 1e-5 && p[2].abs() < 1e-5));
    for (draw, expected) in [
        (json!({"body": "nothing", "boxes": [{"low": [0, 0, 0], "high": [0, 0, 0]}]}),
         "task.terms.reset_noise.mocap[0].body: unknown mocap body \"nothing\" (mocap bodies: \"target\")"),
        (json!({"body": "target"}), "task.terms.reset_noise.mocap[0]: expected exactly one of boxes or polar"),
        (json!({"body": "target", "polar": {"plane": "yz", "center": [0, 0, 0], "radius": [0, 1], "angle": [0, 1]}}),
         "mocap[0].polar.plane: expected \"xy\" or \"xz\", got \"yz\""),
        (json!({"body": "target", "boxes": [{"weight": 0, "low": [0, 0, 0], "high": [0, 0, 0]}]}),
         "mocap[0].boxes[0].weight: expected a weight > 0, got 0"),
        (json!({"body": "target", "boxes": [{"low": [0, 0, 1], "high": [0, 0, 0]}]}),
         "mocap[0].boxes[0].high: expected high >= low in every coordinate"),
        (json!({"body": "target", "polar": {"plane": "xy", "center": [0, 0, 0], "radius": [1, 0], "angle": [0, 1]}}),
         "mocap[0].polar.radius: expected min <= max, got 1 and 0"),
        (json!({"body": "target", "boxes": [{"low": [0, 0, 0], "high": [0, 0, 0]}],
                "polar": {"plane": "xy", "center": [0, 0, 0], "radius": [0, 1], "angle": [0, 1]}}),
         "task.terms.reset_noise.mocap[0]: expected exactly one of boxes or polar"),
    ] {
        let config = EnvConfig {
            units: Units::Si,
            task: Some(TaskSpec {
                kind: TaskKind::Terms(
                    TermsTask::from_json(&json!({"terms": [], "reset_noise": {"mocap": [draw]}}).to_string())
                        .expect("parses"),
                ),
                action_cost: 0.0,
            }),
            ..EnvConfig::default()
        };
        let err = RobotEnv::from_json(&doc.to_string(), config).err().expect("refused").to_string();
        assert!(err.contains(expected), "{err}\n  expected: {expected}");
    }
    let twice = json!({"body": "target", "boxes": [{"low": [0, 0, 0], "high": [0, 0, 0]}]});
    let config = EnvConfig {
        units: Units::Si,
        task: Some(TaskSpec {
            kind: TaskKind::Terms(
                TermsTask::from_json(
                    &json!({"terms": [], "reset_noise": {"mocap": [twice.clone(), twice]}})
                        .to_string(),
                )
                .expect("parses"),
            ),
            action_cost: 0.0,
        }),
        ..EnvConfig::default()
    };
    let err = RobotEnv::from_json(&doc.to_string(), config)
        .err()
        .expect("refused")
        .to_string();
    assert!(
        err.contains(
            "task.terms.reset_noise.mocap[1].body: the mocap body is drawn by an earlier entry too"
        ),
        "{err}"
    );
}
