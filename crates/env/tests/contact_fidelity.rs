//! Contact fidelity at the default step (1/240 s, 5 substeps): a ball dropped on a plane
//! rebounds to e² of its drop height.

mod common;

use common::env_with;
use gymfleet_env::{ActionType, EnvConfig, TaskKind, TaskSpec, TermsTask};
use serde_json::json;

const RADIUS_MM: f64 = 20.0;

/// The rebound apex over the drop height for a ball of restitution `e` on a plane of
/// restitution `e`, reaching the plane at `speed` m/s.
fn rebound_ratio(e: f64, speed: f64) -> (f64, f64) {
    let g = 9.81;
    let drop_mm = speed * speed / (2.0 * g) * 1000.0;
    let doc = json!({
        "materials": {"bouncy": {"restitution": e, "friction": 0.5}},
        "parts": [
            {"name": "Ground", "primitive": {"type": "plane"}, "material": "bouncy"},
            {"name": "Ball", "primitive": {"type": "sphere", "radius": RADIUS_MM},
             "material": "bouncy"}
        ],
        "assembly": {"instances": [
            {"part": "Ground", "name": "ground"},
            {"part": "Ball", "name": "ball", "position": {"x": 0, "y": 0, "z": RADIUS_MM + drop_mm}}
        ]}
    });
    let mut env = env_with(&doc, EnvConfig::with_end_effectors(["ball"]));
    let mut lowest = f64::MAX;
    let mut apex = f64::MIN;
    let mut rising = false;
    let mut previous = RADIUS_MM + drop_mm;
    for _ in 0..2000 {
        let obs = env
            .step(ActionType::Torque, &[])
            .expect("steps")
            .observation
            .to_flat();
        let z = f64::from(obs[2]);
        lowest = lowest.min(z);
        if z > previous {
            rising = true;
            apex = apex.max(z);
        } else if rising {
            break;
        }
        previous = z;
    }
    (
        (apex - RADIUS_MM) / drop_mm,
        (RADIUS_MM - lowest) / RADIUS_MM,
    )
}

/// Issue S's bar: e² within ±0.05 for e in {0.5, 0.8, 1.0} at 0.3, 1 and 3 m/s, and
/// penetration (at the step ends an observer sees) under 15 % of the radius. Every case is in
/// fact within 0.01 of e²; [`SHARPER`] holds that, so a contact that starts losing energy
/// shows here before it reaches the issue's bar.
///
/// History of the hardest case, e = 1 at 0.3 m/s (a 4.6 mm drop, 1/1200 s substeps): 0.884
/// before patch 18 of `vendor/rapier3d` (the target taken at the step's start, not at impact);
/// 0.936 before patch 25, which bounces at the end of the substep of impact instead of the
/// step's, and from the approach speed of the substep in which the ball would cross the floor:
/// the bounce that keeps what semi-implicit Euler conserves (`v²/2 + g·z − g·h·v/2`); bounced
/// from the speed of its last free substep, it lost `2·g·h/v` of the ratio, 5.4 %.
#[test]
fn a_dropped_ball_rebounds_to_e_squared_of_its_height() {
    let mut report = Vec::new();
    let mut failures = Vec::new();
    for e in [0.5, 0.8, 1.0] {
        for speed in [0.3, 1.0, 3.0] {
            let (ratio, penetration) = rebound_ratio(e, speed);
            let line = format!(
                "e {e} at {speed} m/s: {ratio:.3} (e² = {:.3}), penetration {:.1} % of r",
                e * e,
                penetration * 100.0
            );
            let held = (ratio - e * e).abs() <= 0.05 && penetration < 0.15;
            if !held || (ratio - e * e).abs() > SHARPER {
                failures.push(line.clone());
            }
            report.push(line);
        }
    }
    println!("{}", report.join("\n"));
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// How close to e² every drop comes today (the largest miss is 0.008, e = 0.5 at 1 m/s).
const SHARPER: f64 = 0.015;

/// A 20 mm cube (its local frame at a corner) on a plane tilted `tilt_deg` about x, both of
/// friction `mu`; returns the cube's positions (mm) along the observation, every step.
fn cube_on_ramp(tilt_deg: f64, mu: f64, steps: usize) -> Vec<[f64; 3]> {
    let t = tilt_deg.to_radians();
    // The cube rests on the ramp: its bottom face on the plane, turned with it.
    let (s, c) = (t.sin(), t.cos());
    let lift = 0.2; // mm above the plane
    let doc = json!({
        "materials": {"ramp": {"friction": mu}},
        "parts": [
            {"name": "Ground", "primitive": {"type": "plane"}, "material": "ramp"},
            {"name": "Cube", "primitive": {"type": "cube", "size": {"x": 20, "y": 20, "z": 20}},
             "material": "ramp"}
        ],
        "assembly": {"instances": [
            {"part": "Ground", "name": "ground", "rotation": {"x": tilt_deg, "y": 0, "z": 0}},
            {"part": "Cube", "name": "cube", "rotation": {"x": tilt_deg, "y": 0, "z": 0},
             "position": {"x": -10, "y": -lift * s, "z": lift * c}}
        ]}
    });
    let mut env = env_with(&doc, EnvConfig::with_end_effectors(["cube"]));
    (0..steps)
        .map(|_| {
            let o = env
                .step(ActionType::Torque, &[])
                .expect("steps")
                .observation
                .to_flat();
            [f64::from(o[0]), f64::from(o[1]), f64::from(o[2])]
        })
        .collect()
}

/// Sliding down a 20° ramp of friction 0.2: the acceleration along the slope is
/// g(sin θ − μ cos θ) within 5 % (issue S).
#[test]
fn a_cube_slides_down_a_ramp_at_g_sin_minus_mu_g_cos() {
    let (tilt, mu) = (20f64, 0.2);
    let dt = 1.0 / 240.0;
    let path = cube_on_ramp(tilt, mu, 240);
    // Distance along the slope (mm) from the position at step 24 (after landing) to 240.
    let along = |p: [f64; 3], q: [f64; 3]| {
        let (d_y, d_z) = (q[1] - p[1], q[2] - p[2]);
        (d_y * d_y + d_z * d_z).sqrt() / 1000.0
    };
    let (k0, k1, k2) = (24usize, 132usize, 239usize);
    let t1 = (k1 - k0) as f64 * dt;
    let t2 = (k2 - k0) as f64 * dt;
    let (s1, s2) = (along(path[k0], path[k1]), along(path[k0], path[k2]));
    // s = v0·t + a·t²/2 at two times: solve for a.
    let a = 2.0 * (s2 / t2 - s1 / t1) / (t2 - t1);
    let t = tilt.to_radians();
    let expected = 9.81 * (t.sin() - mu * t.cos());
    println!("slides at {a:.4} m/s², expected {expected:.4}");
    assert!(
        (a - expected).abs() < 0.05 * expected,
        "slides at {a:.3} m/s², g(sin θ − μ cos θ) = {expected:.3}"
    );
    assert!(path[k2][1] < path[k0][1], "it slides down (−y)");
}

/// A cube at rest on the floor stays put: it moves less than 0.01 mm in 10 s (issue S).
#[test]
fn a_cube_at_rest_on_the_floor_stays_put() {
    let path = cube_on_ramp(0.0, 0.5, 2640);
    let settled = path[239];
    let last = path[2639];
    let moved = ((last[0] - settled[0]).powi(2)
        + (last[1] - settled[1]).powi(2)
        + (last[2] - settled[2]).powi(2))
    .sqrt();
    println!("moved {moved:e} mm in 10 s, resting at z = {} mm", last[2]);
    assert!(moved < 0.01, "moved {moved} mm in 10 s");
}

/// A 100 mm cube (1 kg) on MuJoCo's planar root: a slide along x from the floor, a slide
/// along z and a hinge about y at the cube's centre, through two 1 mg helper frames (what the
/// MJCF converter builds for HalfCheetah, Hopper and Walker2d). Pushed along x with `force`
/// N for 0.5 s, then let go; returns the x velocities (m/s), every step.
fn planar_box_velocities(force: f32) -> Vec<f64> {
    let helper = |name: &str| {
        json!({"part": "Helper", "name": name, "position": {"x": 0, "y": 0, "z": 50.5},
               "inertial": {"mass": 1e-6}, "collision": {"group": 0, "mask": 0}})
    };
    let joint = |name: &str, kind: &str, parent: &str, child: &str, axis: [f64; 3]| {
        json!({"name": name, "type": kind, "parent": parent, "child": child,
               "anchor": {"x": 0, "y": 0, "z": 50.5},
               "axis": {"x": axis[0], "y": axis[1], "z": axis[2]}})
    };
    let doc = json!({
        "materials": {"m": {"friction": 0.4}},
        "parts": [
            {"name": "Floor", "primitive": {"type": "plane"}, "material": "m"},
            {"name": "Helper", "primitive": {"type": "sphere", "radius": 1}},
            {"name": "Box", "primitive": {"type": "cube", "size": {"x": 100, "y": 100, "z": 100}},
             "material": "m"}
        ],
        "assembly": {
            "instances": [
                {"part": "Floor", "name": "floor"},
                helper("slid"), helper("lifted"),
                {"part": "Box", "name": "box", "position": {"x": -50, "y": -50, "z": 0.5}}
            ],
            "joints": [
                joint("rootx", "prismatic", "floor", "slid", [1.0, 0.0, 0.0]),
                joint("rootz", "prismatic", "slid", "lifted", [0.0, 0.0, 1.0]),
                joint("rooty", "revolute", "lifted", "box", [0.0, 1.0, 0.0])
            ]
        }
    });
    let mut env = env_with(&doc, EnvConfig::with_end_effectors(["box"]));
    let (actions, dofs) = (env.spec().action_dim, env.spec().num_dofs);
    (0..240)
        .map(|k| {
            let mut a = vec![0.0f32; actions];
            a[0] = if k < 120 { force } else { 0.0 };
            let o = env
                .step(ActionType::Torque, &a)
                .expect("steps")
                .observation
                .to_flat();
            f64::from(o[dofs]) / 1000.0
        })
        .collect()
}

/// Regression (vendored Rapier patch 21): friction on a planar chain. The contact's friction
/// row across the plane (along y, where the chain cannot move) had an effective mass of
/// rounding noise inverted to 1e18; its impulse filled the friction cone both rows share, so
/// the cube kept a tenth of its Coulomb friction (it slid at −0.41 m/s² instead of −3.92,
/// and was pushed at 19.7 m/s² instead of 16.1), and PPO learned a HalfCheetah gait at 19 m/s
/// on it. Pushed with 12 N and sliding free, it now accelerates at F/m − μg and slows at μg,
/// both within 2 %.
#[test]
fn a_box_on_a_planar_chain_slides_with_coulomb_friction() {
    let (force, mu, g, dt) = (12.0, 0.4, 9.81, 1.0 / 240.0);
    let v = planar_box_velocities(force as f32);
    // From step 24 (settled on the floor) to 119 while pushed; 143 to 239 while sliding free.
    let pushed = (v[119] - v[23]) / (96.0 * dt);
    let sliding = (v[239] - v[143]) / (96.0 * dt);
    let (expect_pushed, expect_sliding) = (force - mu * g, -mu * g);
    println!("pushed {pushed:.3} m/s² (F/m − μg = {expect_pushed:.3}); sliding {sliding:.3} (−μg = {expect_sliding:.3})");
    assert!(v[239] > 0.1, "still sliding at the end: {} m/s", v[239]);
    assert!(
        (pushed - expect_pushed).abs() < 0.02 * expect_pushed,
        "pushed at {pushed:.3} m/s², expected {expect_pushed:.3}"
    );
    assert!(
        (sliding - expect_sliding).abs() < 0.02 * expect_sliding.abs(),
        "slides at {sliding:.3} m/s², expected {expect_sliding:.3}"
    );
}

/// The lowest height (mm) of a 20 mm ball's centre over a floor whose top face is at
/// z = 0 (a plane, or a 100×100×`plate_mm` plate) after falling from `drop_mm` under
/// `g` m/s², stepping `dt`.
fn lowest_after_a_fall(plate_mm: Option<f64>, drop_mm: f64, g: f64, dt: f64) -> f64 {
    let (floor, at) = match plate_mm {
        Some(t) => (
            json!({"type": "cube", "size": {"x": 100, "y": 100, "z": t}}),
            json!({"x": -50, "y": -50, "z": -t}),
        ),
        None => (json!({"type": "plane"}), json!({"x": 0, "y": 0, "z": 0})),
    };
    let doc = json!({
        "simulation": {"gravity": {"x": 0, "y": 0, "z": -g}},
        "parts": [
            {"name": "Floor", "primitive": floor},
            {"name": "Ball", "primitive": {"type": "sphere", "radius": RADIUS_MM}}
        ],
        "assembly": {"instances": [
            {"part": "Floor", "name": "floor", "position": at},
            {"part": "Ball", "name": "ball", "position": {"x": 0, "y": 0, "z": RADIUS_MM + drop_mm}}
        ]}
    });
    let config = EnvConfig {
        dt,
        ..EnvConfig::with_end_effectors(["ball"])
    };
    let mut env = env_with(&doc, config);
    let mut lowest = f64::MAX;
    // Half as long again as the fall takes, and 40 steps more.
    let fall = (2.0 * drop_mm / 1000.0 / g).sqrt();
    for _ in 0..(1.5 * fall / dt) as usize + 40 {
        let o = env
            .step(ActionType::Torque, &[])
            .expect("steps")
            .observation
            .to_flat();
        lowest = lowest.min(f64::from(o[2]));
    }
    lowest
}

/// Collision detection runs once per step; what it cannot foresee, the continuous pass
/// (vendored Rapier's CCD) catches. A ball falling 2 m reaches the floor at 6, 20 and
/// 40 m/s (up to 1.3 m, 33 ball diameters, in one 1/30 s step): it never passes through a
/// 2 mm plate, nor sinks into a plane, by more than 15 % of its radius.
///
/// Not met yet, and left out of the assertion: a plane at 20 and 40 m/s. Parry has no
/// nonlinear cast against a half-space, so the CCD never clamps a body to a plane (patch 23
/// of `vendor/rapier3d` skips that cast while a body is clear of the plane, the same
/// answer for less), and the ball, predicted by soft CCD alone, sinks below the plane
/// within the step before the contact pushes it back (2026-11-27: its centre reached
/// −47 mm at 20 m/s). At the speeds of a robot's feet (issue S's 0.3–3 m/s) it holds.
const PLANE_NOT_YET: [(f64, f64); 2] = [(100.0, 1.0 / 30.0), (400.0, 1.0 / 30.0)];

#[test]
fn a_fast_ball_stops_on_a_thin_plate_and_on_a_plane() {
    let mut report = Vec::new();
    let mut failures = Vec::new();
    for plate in [Some(2.0), None] {
        for (g, dt) in [
            (9.81, 1.0 / 240.0),
            (100.0, 1.0 / 30.0),
            (400.0, 1.0 / 30.0),
        ] {
            let lowest = lowest_after_a_fall(plate, 2000.0, g, dt);
            let line = format!("floor {plate:?} mm, g {g}, dt {dt:.4}: centre at {lowest:.1} mm");
            let known = plate.is_none() && PLANE_NOT_YET.contains(&(g, dt));
            // Sunk or passed through, or (a check that could not fail) never down to the floor.
            let wrong = lowest <= RADIUS_MM * 0.85 || lowest > RADIUS_MM + 1.0;
            if wrong && !known {
                failures.push(line.clone());
            }
            report.push(line);
        }
    }
    println!("{}", report.join("\n"));
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// How issue F's ball hangs: free, or on a vertical slide from a post aside (a multibody
/// link: Rapier's other contact path).
#[derive(Clone, Copy, Debug)]
enum Mount {
    Free,
    Slide,
}

/// Issue F's scene: a 5 mm ball (density 1000, friction 0.5) dropped on a 10 mm-thick
/// 100 × 100 mm box floor, both of restitution `e`, reaching it at `speed` m/s, stepped at
/// (`dt`, `substeps`). Returns the rebound over the drop height.
///
/// The rebound is read from the first step end after the impact at which the ball is in the
/// air again (or leaving the floor), from its height `z` over the floor and vertical velocity
/// `v` (its `body_velocity` term): semi-implicit Euler with substeps `h` keeps
/// `v²/2 + g·z − g·h·v/2` exactly in free flight, so that value over `g` is the height the
/// simulated flight rises to, whichever step end of the flight it is read at, however coarse
/// the step (at the default step it is within 0.03 of `z + v²/2g`). The drop starts at rest,
/// where the value is `g` times the drop height.
fn small_ball_rebound(e: f64, speed: f64, dt: f64, substeps: u32, mount: Mount) -> Option<f64> {
    const R: f64 = 5.0;
    let g = 9.81;
    let drop_mm = speed * speed / (2.0 * g) * 1000.0;
    let floor =
        json!({"part": "Floor", "name": "floor", "position": {"x": -50, "y": -50, "z": -10}});
    let ball =
        json!({"part": "Ball", "name": "ball", "position": {"x": 0, "y": 0, "z": R + drop_mm}});
    let (instances, joints) = match mount {
        Mount::Free => (json!([floor, ball]), json!([])),
        Mount::Slide => {
            let mut floor = floor;
            floor["fixed"] = json!(true);
            let post = json!({"part": "Floor", "name": "post", "position": {"x": 500, "y": 0, "z": 0},
                              "collision": {"group": 0, "mask": 0}});
            let slide = json!({"type": "prismatic", "parent": "post", "child": "ball",
                               "anchor": {"x": 0, "y": 0, "z": 0}, "axis": {"x": 0, "y": 0, "z": 1},
                               "actuated": false});
            (json!([post, floor, ball]), json!([slide]))
        }
    };
    let doc = json!({
        "materials": {"bouncy": {"restitution": e, "friction": 0.5}},
        "parts": [
            {"name": "Floor", "primitive": {"type": "cube", "size": {"x": 100, "y": 100, "z": 10}},
             "material": "bouncy"},
            {"name": "Ball", "primitive": {"type": "sphere", "radius": R}, "material": "bouncy"}
        ],
        "assembly": {"instances": instances, "joints": joints}
    });
    let terms = json!({"terms": [
        {"name": "vz", "weight": 0, "value": {"body_velocity": ["ball"], "component": 5}}
    ]});
    let config = EnvConfig {
        dt,
        substeps,
        task: Some(TaskSpec {
            kind: TaskKind::Terms(TermsTask::from_json(&terms.to_string()).expect("terms")),
            action_cost: 0.0,
        }),
        ..EnvConfig::with_end_effectors(["ball"])
    };
    let mut env = env_with(&doc, config);
    let h = dt / f64::from(substeps);
    let impact = speed / g;
    for k in 1..=((2.0 / dt) as usize) {
        let obs = env
            .step(ActionType::Torque, &[])
            .expect("steps")
            .observation
            .to_flat();
        // The ball's height (mm): its end effector's, or its slide's position.
        let z = match mount {
            Mount::Free => f64::from(obs[2]),
            Mount::Slide => R + drop_mm + f64::from(obs[0]),
        };
        let v = f64::from(env.term_values()[0]);
        if k as f64 * dt > impact && (z > R + 0.05 || v > 0.0) {
            let kept = v * v / 2.0 + g * (z - R) / 1000.0 - g * h * v / 2.0;
            return Some(kept / (g * drop_mm / 1000.0));
        }
    }
    None
}

/// The settings the rebound holds at: the default step, and each suite id's (its MuJoCo
/// timestep times `frame_skip`, in `frame_skip` substeps).
const SETTINGS: [(&str, f64, u32); 7] = [
    ("the default step", 1.0 / 240.0, 5),
    ("HalfCheetah, Ant, Pusher, InvertedDoublePendulum", 0.05, 5),
    ("Hopper, Walker2d", 0.008, 4),
    ("Humanoid, HumanoidStandup", 0.015, 5),
    ("Swimmer", 0.04, 4),
    ("Reacher", 0.02, 2),
    ("InvertedPendulum", 0.04, 2),
];

/// Issue F's bar for `mount`: e² within ±0.05 for e in {0.5, 0.8, 1.0} at 0.3, 1 and 3 m/s, at
/// every setting of [`SETTINGS`]; every case is in fact within [`SHARPER_F`].
fn assert_small_ball_rebounds(mount: Mount) {
    let mut report = Vec::new();
    let mut failures = Vec::new();
    for (name, dt, substeps) in SETTINGS {
        for e in [0.5, 0.8, 1.0] {
            for speed in [0.3, 1.0, 3.0] {
                let ratio = small_ball_rebound(e, speed, dt, substeps, mount);
                let line = format!(
                    "{mount:?}, {name} ({dt:.4} s, {substeps} substeps): e {e} at {speed} m/s: {ratio:.4?} (e² = {:.2})",
                    e * e
                );
                if ratio.is_none_or(|r| (r - e * e).abs() > SHARPER_F) {
                    failures.push(line.clone());
                }
                report.push(line);
            }
        }
    }
    println!("{}", report.join("\n"));
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// How close to e² every case of issue F comes today.
const SHARPER_F: f64 = 0.01;

/// History (vendored Rapier patch 39): before it, 22 of the 63 cases missed the bar, all at
/// the suite ids' coarse steps. At 10 ms substeps e = 1 from 0.3 m/s came back to 3.2 (the
/// ball, at rest 4.6 mm up at the step's start, was not predicted to reach the floor within
/// the step, and the CCD put it there at its free-fall speed) and e = 0.5 to 0.64; at 10 ms
/// substeps in steps of two, e = 1 to 0.64 (stopped at the floor within the substep, it lost
/// what it had gained since the substep began) and e = 0.5 to 0.08.
#[test]
fn a_small_free_ball_rebounds_to_e_squared_at_the_default_and_every_suite_ids_step() {
    assert_small_ball_rebounds(Mount::Free);
}

/// The same on Rapier's multibody contact path: before patch 39 it bounced only after the
/// step's last substep, from the approach speed at the step's start, and 45 of the 63 cases
/// missed the bar (e = 1 at 0.3 m/s: 0.88 at the default step).
#[test]
fn a_small_ball_on_a_slide_rebounds_to_e_squared_at_the_default_and_every_suite_ids_step() {
    assert_small_ball_rebounds(Mount::Slide);
}
