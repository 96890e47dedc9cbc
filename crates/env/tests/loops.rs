//! Closed kinematic chains against their closed forms: a crank-rocker four-bar driven at a
//! constant crank speed, a slider-crank, a passive four-bar swinging under gravity (its
//! loop stays closed and its energy is kept), and a four-bar under 100× its gravity torque.

mod common;

use common::{env_with, wrap_deg};
use gymfleet_env::{ActionType, EnvConfig};
use gymfleet_physics::{RobotWorld, Units, WorldOptions};
use serde_json::{json, Value};

/// Four-bar link lengths (mm): crank a, coupler b, rocker c, ground d (a Grashof
/// crank-rocker: the crank is the shortest link and s + l < p + q).
const A: f64 = 40.0;
const B: f64 = 120.0;
const C: f64 = 100.0;
const D: f64 = 110.0;
/// The crank's angle in the document's pose, deg (counterclockwise in the x–z plane).
const CRANK0: f64 = 60.0;

/// The rocker's pin B (x, z in mm) at crank angle `theta` (rad): the crossing of the
/// coupler's circle about A and the rocker's about O4 = (D, 0), on the upper branch.
fn pin_b(theta: f64) -> [f64; 2] {
    let a = [A * theta.cos(), A * theta.sin()];
    let o4 = [D, 0.0];
    let (dx, dz) = (o4[0] - a[0], o4[1] - a[1]);
    let dist = (dx * dx + dz * dz).sqrt();
    // Along A→O4 from A to the chord, then across it.
    let along = (B * B - C * C + dist * dist) / (2.0 * dist);
    let across = (B * B - along * along).sqrt();
    let (ux, uz) = (dx / dist, dz / dist);
    // The branch with B above the line A→O4 (the document's assembly).
    [
        a[0] + along * ux - across * uz,
        a[1] + along * uz + across * ux,
    ]
}

fn crank_pin(theta: f64) -> [f64; 2] {
    [A * theta.cos(), A * theta.sin()]
}

/// A 5 mm sphere named `name` centred at (x, z); colliding with nothing.
fn ball(name: &str, at: [f64; 2]) -> Value {
    json!({"part": "Ball", "name": name, "position": {"x": at[0], "y": 0, "z": at[1]},
           "collision": {"group": 0, "mask": 0}})
}

/// A revolute joint about −y (so that angles grow counterclockwise in the x–z plane).
fn pin(name: &str, parent: &str, child: &str, at: [f64; 2], actuated: bool) -> Value {
    json!({"name": name, "type": "revolute", "parent": parent, "child": child,
           "anchor": {"x": at[0], "y": 0, "z": at[1]}, "axis": {"x": 0, "y": -1, "z": 0},
           "actuated": actuated})
}

fn parts() -> Value {
    json!([
        {"name": "Base", "primitive": {"type": "cube", "size": {"x": 10, "y": 10, "z": 10}}},
        {"name": "Ball", "primitive": {"type": "sphere", "radius": 5}}
    ])
}

/// The crank-rocker: the ground, a crank O2→A, a coupler A→B and a rocker O4→B, each a
/// ball at its link's midpoint. The crank's joint is driven; the coupler–rocker pin closes
/// the loop.
fn four_bar(gravity: bool) -> Value {
    let t = CRANK0.to_radians();
    let (a, b) = (crank_pin(t), pin_b(t));
    let mid = |p: [f64; 2], q: [f64; 2]| [(p[0] + q[0]) / 2.0, (p[1] + q[1]) / 2.0];
    json!({
        "parts": parts(),
        "simulation": {"gravity": {"x": 0, "y": 0, "z": if gravity { -9.81 } else { 0.0 }}},
        "assembly": {
            "instances": [
                {"part": "Base", "name": "ground", "position": {"x": 40, "y": 40, "z": -60},
                 "collision": {"group": 0, "mask": 0}},
                ball("crank", mid([0.0, 0.0], a)),
                ball("coupler", mid(a, b)),
                ball("rocker", mid([D, 0.0], b))
            ],
            "joints": [
                pin("crank", "ground", "crank", [0.0, 0.0], true),
                pin("elbow", "crank", "coupler", a, false),
                pin("rocker", "ground", "rocker", [D, 0.0], false),
                pin("closer", "coupler", "rocker", b, false)
            ]
        }
    })
}

/// Angle of the vector p→q, rad.
fn heading(p: [f64; 2], q: [f64; 2]) -> f64 {
    (q[1] - p[1]).atan2(q[0] - p[0])
}

/// Drives the crank of a four-bar env (the crank-rocker's link lengths, its crank at
/// `CRANK0` in the document's pose) at one turn per second for `steps` steps; returns the
/// last joint positions and the largest error of the rocker (joint 2) against the closed
/// form at the measured crank angle, deg.
fn drive_and_check_rocker(env: &mut gymfleet_env::RobotEnv, steps: usize) -> (Vec<f32>, f64) {
    let t0 = CRANK0.to_radians();
    let rocker0 = heading([D, 0.0], pin_b(t0));
    let mut worst = 0.0f64;
    let mut q = Vec::new();
    for _ in 0..steps {
        q = env
            .step(ActionType::Velocity, &[360.0])
            .expect("steps")
            .observation
            .joint_positions;
        let theta = t0 + f64::from(q[0]).to_radians();
        let rocker = (heading([D, 0.0], pin_b(theta)) - rocker0).to_degrees();
        worst = worst.max(wrap_deg(f64::from(q[2]) - rocker).abs());
    }
    (q, worst)
}

#[test]
fn a_driven_crank_rocker_follows_its_closed_form_position_solution() {
    let t0 = CRANK0.to_radians();
    let rocker0 = heading([D, 0.0], pin_b(t0));
    let coupler0 = heading(crank_pin(t0), pin_b(t0));
    let mut env = env_with(&four_bar(true), EnvConfig::with_end_effectors(["coupler"]));
    let spec = env.spec().clone();
    assert_eq!(spec.action_dim, 1, "only the crank is driven");
    assert_eq!(
        spec.num_dofs, 4,
        "every joint is observed, the loop's closer too"
    );
    let (mut worst_rocker, mut worst_closer, mut worst_point) = (0.0f64, 0.0f64, 0.0f64);
    let mut turned = 0.0;
    // One turn per second for 2.5 s.
    for _ in 0..600 {
        let obs = env
            .step(ActionType::Velocity, &[360.0])
            .expect("steps")
            .observation;
        let q: Vec<f64> = obs.joint_positions.iter().map(|&v| f64::from(v)).collect();
        let theta = t0 + q[0].to_radians();
        turned = q[0];
        let (a, b) = (crank_pin(theta), pin_b(theta));
        // The rocker (a tree joint) against the closed form at the measured crank angle.
        let rocker = heading([D, 0.0], b) - rocker0;
        worst_rocker = worst_rocker.max(wrap_deg(q[2] - rocker.to_degrees()).abs());
        // The loop's closing pin, observed from its two bodies: the rocker's angle to the
        // coupler, from the document's pose.
        let closer = (heading([D, 0.0], b) - rocker0) - (heading(a, b) - coupler0);
        worst_closer = worst_closer.max(wrap_deg(q[3] - closer.to_degrees()).abs());
        // The coupler point (the coupler ball's centre, the middle of A–B) on its path.
        let p = obs.end_effector_poses[0];
        let expected = [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0];
        let dist = (f64::from(p[0]) - expected[0]).hypot(f64::from(p[2]) - expected[1]);
        worst_point = worst_point.max(dist);
    }
    println!(
        "crank turned {turned:.1}°; rocker within {worst_rocker:.5}°, closing pin within {worst_closer:.5}°, coupler point within {worst_point:.5} mm"
    );
    assert!(turned > 720.0, "two full turns at least, got {turned}°");
    assert!(worst_rocker < 0.01, "rocker off by {worst_rocker}°");
    assert!(worst_closer < 0.01, "closing pin off by {worst_closer}°");
    assert!(worst_point < 0.01, "coupler point off by {worst_point} mm");
}

/// Crank r, rod l (mm) of the slider-crank.
const R: f64 = 30.0;
const L: f64 = 100.0;

#[test]
fn a_slider_crank_slider_is_at_r_cos_plus_the_rods_reach() {
    let t0 = 90f64.to_radians();
    let slider_x = |t: f64| R * t.cos() + (L * L - R * R * t.sin().powi(2)).sqrt();
    let a = [R * t0.cos(), R * t0.sin()];
    let s0 = [slider_x(t0), 0.0];
    let doc = json!({
        "parts": parts(),
        "assembly": {
            "instances": [
                {"part": "Base", "name": "ground", "position": {"x": 40, "y": 40, "z": -60},
                 "collision": {"group": 0, "mask": 0}},
                ball("crank", [a[0] / 2.0, a[1] / 2.0]),
                ball("rod", [(a[0] + s0[0]) / 2.0, (a[1] + s0[1]) / 2.0]),
                ball("slider", s0)
            ],
            "joints": [
                pin("crank", "ground", "crank", [0.0, 0.0], true),
                pin("wrist", "crank", "rod", a, false),
                {"name": "slide", "type": "prismatic", "parent": "ground", "child": "slider",
                 "anchor": {"x": s0[0], "y": 0, "z": 0}, "axis": {"x": 1, "y": 0, "z": 0},
                 "actuated": false},
                pin("gudgeon", "rod", "slider", s0, false)
            ]
        }
    });
    let mut env = env_with(&doc, EnvConfig::with_end_effectors(["slider"]));
    let mut worst = 0.0f64;
    let mut turned = 0.0;
    for _ in 0..600 {
        let obs = env
            .step(ActionType::Velocity, &[360.0])
            .expect("steps")
            .observation;
        let q: Vec<f64> = obs.joint_positions.iter().map(|&v| f64::from(v)).collect();
        turned = q[0];
        let theta = t0 + q[0].to_radians();
        // The slide joint's position is measured from the document's pose.
        let x = s0[0] + q[2];
        worst = worst.max((x - slider_x(theta)).abs());
    }
    println!(
        "crank turned {turned:.1}°; slider within {worst:.5} mm of r cos θ + √(l² − r² sin² θ)"
    );
    assert!(turned > 720.0, "two full turns at least, got {turned}°");
    assert!(worst < 0.01, "slider off by {worst} mm");
}

/// The kinetic and the potential energy (J) of `world`'s balls, and the largest loop gap
/// (mm, deg).
fn energy_and_gap(world: &RobotWorld, balls: &[usize], g: f64) -> (f64, f64, f64, f64) {
    let state = world.dynamic_state();
    let r = 0.005f64;
    let m = 1000.0 * 4.0 / 3.0 * std::f64::consts::PI * r.powi(3);
    let i = 0.4 * m * r * r;
    let (mut kinetic, mut potential) = (0.0, 0.0);
    for &b in balls {
        let motion = &state.bodies[b];
        let v2: f64 = motion.linvel.iter().map(|&v| f64::from(v).powi(2)).sum();
        let w2: f64 = motion.angvel.iter().map(|&w| f64::from(w).powi(2)).sum();
        let z = f64::from(world.body_pose(Units::Si, b)[2]);
        kinetic += 0.5 * m * v2 + 0.5 * i * w2;
        potential += m * g * z;
    }
    let (mut gap, mut angle) = (0.0f64, 0.0f64);
    for (d, a) in world.loop_gaps() {
        gap = gap.max(d * 1000.0);
        angle = angle.max(a.to_degrees());
    }
    (kinetic, potential, gap, angle)
}

fn world_of(doc: &Value, options: &WorldOptions) -> RobotWorld {
    let assembly = gymfleet_assembly::from_value(doc.clone()).expect("valid");
    RobotWorld::new(&assembly, options).expect("builds")
}

/// Swings the passive four-bar from the document's pose for 10 s at `substeps`; returns its
/// crank's swing (deg), the largest loop gap (mm, deg) and the energy drift as a fraction of
/// the largest kinetic energy it reaches.
fn passive_swing(substeps: u32) -> (f64, f64, f64, f64) {
    let mut doc = four_bar(true);
    doc["assembly"]["joints"][0]["actuated"] = json!(false);
    let options = WorldOptions {
        substeps,
        ..WorldOptions::default()
    };
    let mut world = world_of(&doc, &options);
    let (k0, p0, _, _) = energy_and_gap(&world, &[1, 2, 3], 9.81);
    let (mut gap, mut twist, mut drift, mut most_kinetic) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let (mut lowest, mut highest) = (f64::MAX, f64::MIN);
    let (mut q, mut v) = (vec![0.0f32; 4], vec![0.0f32; 4]);
    for _ in 0..2400 {
        world.step().unwrap();
        let (k, p, g, a) = energy_and_gap(&world, &[1, 2, 3], 9.81);
        gap = gap.max(g);
        twist = twist.max(a);
        drift = drift.max((k + p - k0 - p0).abs());
        most_kinetic = most_kinetic.max(k);
        world.joint_state(Units::Document, &mut q, &mut v);
        lowest = lowest.min(f64::from(q[0]));
        highest = highest.max(f64::from(q[0]));
    }
    let swing = highest - lowest;
    let drift = drift / most_kinetic;
    println!(
        "{substeps} substeps: swung through {swing:.1}° of crank; loop gap at most {gap:.5} mm and {twist:.5}°; energy drift {:.3} % of the largest kinetic energy",
        100.0 * drift
    );
    (swing, gap, twist, drift)
}

/// Released from the document's pose with no damping, the four-bar swings through most of
/// a turn of its crank for 10 s. At the default 5 substeps its loop stays closed within
/// 0.03 mm (0.026 measured); at 40 substeps within 0.01 mm, and its energy within 1 % of the
/// largest kinetic energy it reaches. The drift is the first-order integrator's, not the
/// loop's: it halves with each doubling of the substeps (4.4 % at 5, 2.4 % at 10, 1.2 % at
/// 20, 0.6 % at 40, measured).
#[test]
fn a_passive_four_bar_swings_for_ten_seconds_closed_and_keeps_its_energy() {
    let (swing, gap, twist, _) = passive_swing(5);
    assert!(swing > 90.0, "it swings: {swing}°");
    assert!(gap < 0.03, "the loop opened by {gap} mm");
    assert!(twist < 0.01, "the loop twisted by {twist}°");
    let (swing, gap, twist, drift) = passive_swing(40);
    assert!(swing > 90.0, "it swings: {swing}°");
    assert!(gap < 0.01, "the loop opened by {gap} mm");
    assert!(twist < 0.01, "the loop twisted by {twist}°");
    assert!(drift < 0.01, "energy drifted by {:.3} %", drift * 100.0);
}

/// A constant crank torque of 100× the links' weight at the crank's length, for 10 s: the
/// crank spins up until its joint's damping (0.005 N·m·s/rad) holds it near 2 turns per
/// second, and the loop stays closed within 0.01 mm and every value finite.
#[test]
fn a_four_bar_under_a_hundred_times_its_gravity_torque_stays_closed_and_finite() {
    let mut doc = four_bar(true);
    doc["assembly"]["joints"][0]["damping"] = json!(0.005);
    let m = 1000.0 * 4.0 / 3.0 * std::f64::consts::PI * 0.005f64.powi(3);
    let torque = (100.0 * 3.0 * m * 9.81 * A / 1000.0) as f32;
    let mut env = env_with(&doc, EnvConfig::with_end_effectors(["coupler"]));
    for _ in 0..2400 {
        let r = env.step(ActionType::Torque, &[torque]).expect("steps");
        assert!(
            r.observation.to_flat().iter().all(|v| v.is_finite()),
            "non-finite observation"
        );
    }
    let mut world = world_of(&doc, &WorldOptions::default());
    world.set_command(gymfleet_physics::ActionMode::Torque, &[torque]);
    let mut worst = (0.0f64, 0.0f64);
    for _ in 0..2400 {
        world.step().unwrap();
        let (_, _, gap, angle) = energy_and_gap(&world, &[1, 2, 3], 9.81);
        worst = (worst.0.max(gap), worst.1.max(angle));
    }
    let (mut q, mut v) = (vec![0.0f32; 4], vec![0.0f32; 4]);
    world.joint_state(Units::Document, &mut q, &mut v);
    println!(
        "after 10 s: crank at {:.0}°, {:.0}°/s; loop gap at most {:.5} mm and {:.5}°",
        q[0], v[0], worst.0, worst.1
    );
    assert!(world.is_finite());
    assert!(q[0] > 3600.0, "the torque turns the crank: {}°", q[0]);
    assert!(worst.0 < 0.01, "the loop opened by {} mm", worst.0);
    assert!(worst.1 < 0.01, "the loop twisted by {}°", worst.1);
}

/// Reset noise moves the joints off the loops and leaves the loop's joints at the
/// document's pose, so that every reset starts with the loop closed.
#[test]
fn reset_noise_leaves_a_loop_closed() {
    let mut doc = four_bar(true);
    let t = CRANK0.to_radians();
    let a = crank_pin(t);
    doc["assembly"]["instances"]
        .as_array_mut()
        .expect("instances")
        .push(ball("tail", [a[0] / 2.0, a[1] / 2.0 - 30.0]));
    doc["assembly"]["joints"]
        .as_array_mut()
        .expect("joints")
        .push(pin("tail", "crank", "tail", [a[0] / 2.0, a[1] / 2.0], true));
    let config = EnvConfig {
        reset_noise: 5.0,
        ..EnvConfig::with_end_effectors(["coupler"])
    };
    let mut env = env_with(&doc, config);
    let mut moved_tail = 0.0f32;
    for seed in 0..20 {
        let obs = env.reset(Some(seed));
        let q = &obs.joint_positions;
        assert_eq!(
            &q[..4],
            &[0.0; 4],
            "seed {seed}: the loop's joints start at the document's pose"
        );
        moved_tail = moved_tail.max(q[4].abs());
        assert!(obs.joint_velocities[..4].iter().all(|&v| v == 0.0));
    }
    assert!(
        moved_tail > 1.0,
        "the tail, off the loop, takes the noise: {moved_tail}°"
    );
}

const FOURBAR: &str = include_str!("../../../models/fourbar.json");

/// The four-bar of `models/` (the same link lengths, as bars): driven through two turns,
/// its rocker swings between the closed form's extremes and its loop stays closed.
#[test]
fn the_shipped_four_bar_swings_its_rocker_through_the_closed_forms_range() {
    let doc: Value = serde_json::from_str(FOURBAR).expect("json");
    let t0 = CRANK0.to_radians();
    let rocker0 = heading([D, 0.0], pin_b(t0));
    // The rocker's range over a turn, by the closed form (deg from the document's pose).
    let closed: Vec<f64> = (0..3600)
        .map(|k| {
            (heading([D, 0.0], pin_b(f64::from(k).to_radians() / 10.0)) - rocker0).to_degrees()
        })
        .collect();
    let (lo, hi) = closed
        .iter()
        .fold((f64::MAX, f64::MIN), |(l, h), &v| (l.min(v), h.max(v)));
    let mut env = env_with(&doc, EnvConfig::with_end_effectors(["coupler"]));
    let (mut seen_lo, mut seen_hi) = (f64::MAX, f64::MIN);
    for _ in 0..600 {
        let q = env
            .step(ActionType::Velocity, &[360.0])
            .expect("steps")
            .observation
            .joint_positions;
        seen_lo = seen_lo.min(f64::from(q[2]));
        seen_hi = seen_hi.max(f64::from(q[2]));
    }
    let assembly = gymfleet_assembly::parse(FOURBAR).expect("valid");
    assert_eq!(assembly.joints.iter().filter(|j| j.closes_loop).count(), 1);
    println!("rocker swings [{seen_lo:.3}, {seen_hi:.3}]°; closed form [{lo:.3}, {hi:.3}]°");
    assert!((seen_lo - lo).abs() < 0.05 && (seen_hi - hi).abs() < 0.05);
}

/// A moving four-bar saved and loaded continues bitwise like the env it was saved from.
#[test]
fn a_saved_moving_four_bar_continues_bitwise() {
    let doc: Value = serde_json::from_str(FOURBAR).expect("json");
    let mut env = env_with(&doc, EnvConfig::with_end_effectors(["coupler"]));
    for _ in 0..50 {
        env.step(ActionType::Velocity, &[360.0]).expect("steps");
    }
    let bytes = env.save().expect("saves").encode();
    let state = gymfleet_env::SavedState::decode(&bytes).expect("decodes");
    let mut loaded = gymfleet_env::RobotEnv::from_state(&state).expect("loads");
    for k in 0..200 {
        let action = [if k < 100 { 360.0 } else { -180.0 }];
        let a = env.step(ActionType::Velocity, &action).expect("steps");
        let b = loaded.step(ActionType::Velocity, &action).expect("steps");
        let bits = |o: &gymfleet_env::Observation| -> Vec<u32> {
            o.to_flat().iter().map(|v| v.to_bits()).collect()
        };
        assert_eq!(
            bits(&a.observation),
            bits(&b.observation),
            "step {k} after the load"
        );
    }
}

/// A two-link arm welded to the ground at its tip by a loop-closing fixed joint holds
/// (within 0.1°: the weld over-constrains two DOFs with six, which Gauss–Seidel settles
/// only approximately), and it does so alike whichever of the two bodies the document names
/// the parent: Rapier solves a joint whose second body is fixed wrongly (the arm spun at
/// 2 000°/s), so such a joint is inserted the other way round.
#[test]
fn a_weld_to_the_ground_holds_whichever_body_is_its_parent() {
    let mut runs: Vec<Vec<f32>> = Vec::new();
    for (parent, child) in [("tip", "ground"), ("ground", "tip")] {
        let doc = json!({
            "parts": parts(),
            "assembly": {
                "instances": [
                    {"part": "Base", "name": "ground", "position": {"x": -5, "y": -5, "z": -60},
                     "collision": {"group": 0, "mask": 0}},
                    ball("arm", [50.0, 0.0]),
                    ball("tip", [100.0, 0.0])
                ],
                "joints": [
                    pin("hinge", "ground", "arm", [0.0, 0.0], false),
                    pin("wrist", "arm", "tip", [100.0, 0.0], false),
                    {"name": "weld", "type": "fixed", "parent": parent, "child": child,
                     "actuated": false}
                ]
            }
        });
        let mut world = world_of(&doc, &WorldOptions::default());
        let (mut q, mut v) = (vec![0.0f32; 2], vec![0.0f32; 2]);
        let mut path = Vec::new();
        for _ in 0..240 {
            world.step().unwrap();
            world.joint_state(Units::Document, &mut q, &mut v);
            assert!(
                q.iter().all(|a| a.abs() < 0.1),
                "{parent} -> {child}: {q:?}"
            );
            path.extend(q.iter().copied());
        }
        runs.push(path);
    }
    let apart = runs[0]
        .iter()
        .zip(&runs[1])
        .map(|(a, b)| (a - b).abs())
        .fold(0.0f32, f32::max);
    assert!(
        apart < 1e-3,
        "the same motion either way round: {apart}° apart"
    );
}

/// Domain randomisation (masses, damping, gains) changes the dynamics, never the linkage:
/// across seeds the driven four-bar's rocker still follows the closed form at the measured
/// crank angle.
#[test]
fn a_randomised_four_bar_keeps_its_kinematics() {
    let config = EnvConfig {
        randomize: Some(gymfleet_env::Randomization {
            mass_scale: Some([0.5, 2.0]),
            friction_scale: None,
            damping_scale: Some([0.5, 2.0]),
            gain_scale: Some([0.5, 2.0]),
        }),
        ..EnvConfig::with_end_effectors(["coupler"])
    };
    let mut env = env_with(&four_bar(true), config);
    let mut worst = 0.0f64;
    let mut cranks = Vec::new();
    for seed in 0..4 {
        env.reset(Some(seed));
        let (q, off) = drive_and_check_rocker(&mut env, 120);
        worst = worst.max(off);
        cranks.push(q[0]);
    }
    println!(
        "crank after 0.5 s per seed: {cranks:?}; rocker within {worst:.5}° of the closed form"
    );
    assert!(worst < 0.01, "rocker off by {worst}°");
    assert!(
        cranks.windows(2).any(|w| w[0] != w[1]),
        "the draws change the dynamics: {cranks:?}"
    );
}

/// The bodies a loop-closing joint joins do not collide: with every bar of the shipped
/// four-bar colliding by default, the coupler's and the rocker's ends overlap at the closing
/// pin, and the driven rocker still follows the closed form (a contact there would push the
/// bars apart against the loop). Two things keep the pair apart, each enough alone: the
/// impulse joint has its contacts disabled (`loops.rs`), and the contact filter excludes
/// every jointed pair, loops included (`contact_filter.rs`).
#[test]
fn the_bodies_a_loop_joins_do_not_collide() {
    let mut doc: Value = serde_json::from_str(FOURBAR).expect("json");
    for instance in doc["assembly"]["instances"]
        .as_array_mut()
        .expect("instances")
        .iter_mut()
        .skip(1)
    {
        instance
            .as_object_mut()
            .expect("object")
            .remove("collision");
    }
    let mut env = env_with(&doc, EnvConfig::with_end_effectors(["coupler"]));
    let (_, worst) = drive_and_check_rocker(&mut env, 480);
    println!("colliding bars: rocker within {worst:.5}° of the closed form");
    assert!(worst < 0.01, "rocker off by {worst}°");
}

/// A tendon takes tree joints only: one over a loop-closing joint is refused with its path.
#[test]
fn a_tendon_over_a_loop_closing_joint_is_refused() {
    let mut doc = four_bar(true);
    doc["assembly"]["tendons"] =
        json!([{"name": "t", "joints": [{"joint": "closer", "coef": 1.0}]}]);
    let refused = gymfleet_env::RobotEnv::from_json(&doc.to_string(), EnvConfig::default())
        .err()
        .expect("refused")
        .to_string();
    assert!(
        refused.contains(
            "assembly.tendons[0].joints[0].joint: \"closer\" closes a kinematic loop; a tendon's joints are joints of the tree"
        ),
        "{refused}"
    );
}
