//! Differential check of the gymfleet patches to Rapier (`../rapier3d/PATCHES.md`): the same
//! scenes on rapier3d 0.36.1 as published (`orig`) and on the patched copy (`new`).
//!
//! `cargo run --release` (from this folder) steps a 7-link tree of revolute, prismatic and
//! ball joints with general axes, random start poses and velocities, body torques and gravity,
//! with and without joint limits, and prints per step the largest difference between the two
//! engines relative to the state's scale, beside how far the published engine moves from
//! itself when its start velocities are scaled by 1 ± 1e-6..1e-5 (what rounding alone does).
//! `cargo run --release -- energy` prints the worst energy drift over 10 s of free chains of
//! 2, 6 and 20 links in both engines.
//!
//! The patched engine's own additions (hard limits, joint-space forces) are off here: this
//! checks that everything else integrates as before.

mod energy;
macro_rules! sim {
    ($m:ident, $r:ident) => {
        mod $m {
            use ::$r::prelude::*;
            pub fn run(steps: usize, seed: u64, limits: bool, eps: f32) -> Vec<Vec<f32>> {
                let mut rng = seed;
                let mut rnd = move || {
                    rng ^= rng << 13;
                    rng ^= rng >> 7;
                    rng ^= rng << 17;
                    ((rng >> 11) as f64 / (1u64 << 53) as f64) as f32 * 2.0 - 1.0
                };
                let mut bodies = RigidBodySet::new();
                let mut colliders = ColliderSet::new();
                let mut mbj = MultibodyJointSet::new();
                let mut handles = Vec::new();
                let sizes = [
                    (0.05, 0.05, 0.02),
                    (0.02, 0.02, 0.15),
                    (0.015, 0.015, 0.12),
                    (0.01, 0.03, 0.05),
                    (0.02, 0.01, 0.06),
                    (0.01, 0.01, 0.04),
                    (0.012, 0.02, 0.03),
                ];
                for (k, s) in sizes.iter().enumerate() {
                    let b = if k == 0 {
                        RigidBodyBuilder::fixed()
                    } else {
                        RigidBodyBuilder::dynamic().can_sleep(false)
                    };
                    let h = bodies.insert(
                        b.translation(Vector::new(0.01 * k as f32, 0.0, 0.1 * k as f32))
                            .build(),
                    );
                    let c = ColliderBuilder::cuboid(s.0, s.1, s.2)
                        .density(1000.0 + 300.0 * k as f32)
                        .translation(Vector::new(0.003 * k as f32, -0.002, 0.004))
                        .collision_groups(InteractionGroups::none())
                        .build();
                    colliders.insert_with_parent(c, h, &mut bodies);
                    handles.push(h);
                }
                let axes = [
                    Vector::Y,
                    Vector::new(1.0, 0.3, 0.0).normalize(),
                    Vector::X,
                    Vector::Z,
                    Vector::new(0.2, 0.5, 1.0).normalize(),
                    Vector::Y,
                ];
                // tree: 0-1, 1-2, 2-3 (prismatic), 2-4 (ball), 4-5, 1-6 (branch)
                let edges = [
                    (0usize, 1usize, 0u8),
                    (1, 2, 0),
                    (2, 3, 1),
                    (2, 4, 2),
                    (4, 5, 0),
                    (1, 6, 0),
                ];
                for (e, &(p, c, kind)) in edges.iter().enumerate() {
                    let axis = axes[e];
                    let f1 = Pose::from_parts(
                        Vector::new(0.0, 0.0, 0.05),
                        Rotation::from_rotation_arc(Vector::X, axis),
                    );
                    let f2 = Pose::from_parts(
                        Vector::new(0.0, 0.0, -0.04),
                        Rotation::from_rotation_arc(Vector::X, axis),
                    );
                    let locked = match kind {
                        0 => JointAxesMask::LOCKED_REVOLUTE_AXES,
                        1 => JointAxesMask::LOCKED_PRISMATIC_AXES,
                        _ => JointAxesMask::LOCKED_SPHERICAL_AXES,
                    };
                    let mut builder = GenericJointBuilder::new(locked)
                        .local_frame1(f1)
                        .local_frame2(f2)
                        .contacts_enabled(false);
                    if limits {
                        builder = match kind {
                            0 => builder.limits(JointAxis::AngX, [-0.4, 0.3]),
                            1 => builder.limits(JointAxis::LinX, [-0.02, 0.01]),
                            _ => builder,
                        };
                    }
                    let data = builder.build();
                    mbj.insert(handles[p], handles[c], data, true).unwrap();
                }
                let link = *mbj.rigid_body_link(handles[1]).unwrap();
                let mb = mbj.get_multibody_mut(link.multibody).unwrap();
                mb.damping_mut().fill(0.0);
                mb.forward_kinematics(&bodies, false);
                let n = mb.ndofs();
                let disp: Vec<f32> = (0..n).map(|_| 0.5 * rnd()).collect();
                mb.apply_displacements(&disp);
                for i in 0..n {
                    mb.generalized_velocity_mut()[i] = 3.0 * rnd() * (1.0 + eps);
                }
                mb.forward_kinematics(&bodies, false);
                mb.update_rigid_bodies(&mut bodies, true);
                let torques: Vec<Vector> = (0..handles.len())
                    .map(|_| Vector::new(rnd(), rnd(), rnd()) * 0.02)
                    .collect();
                let params = IntegrationParameters {
                    dt: 1.0 / 240.0,
                    num_solver_iterations: 5,
                    ..IntegrationParameters::default()
                };
                let mut pipeline = PhysicsPipeline::new();
                let mut islands = IslandManager::new();
                let mut bp = BroadPhaseBvh::new();
                let mut np = NarrowPhase::new();
                let mut ij = ImpulseJointSet::new();
                let mut sb = SoftBodySet::new();
                let mut ccd = CCDSolver::new();
                let mut out = Vec::new();
                for _ in 0..steps {
                    for (k, &h) in handles.iter().enumerate().skip(1) {
                        let rb = &mut bodies[h];
                        rb.reset_torques(false);
                        rb.add_torque(torques[k], true);
                    }
                    pipeline.step(
                        Vector::new(0.0, 0.0, -9.81),
                        &params,
                        &mut islands,
                        &mut bp,
                        &mut np,
                        &mut bodies,
                        &mut colliders,
                        &mut ij,
                        &mut mbj,
                        &mut sb,
                        &mut ccd,
                        &(),
                        &(),
                    );
                    let mb = mbj.get_multibody(link.multibody).unwrap();
                    let mut row: Vec<f32> = mb.generalized_velocity().iter().copied().collect();
                    for &h in &handles {
                        let p = bodies[h].translation();
                        row.extend([p.x, p.y, p.z]);
                    }
                    out.push(row);
                }
                out
            }
        }
    };
}
sim!(a, orig);
sim!(b, new);

/// Steps at which the differences are printed (0-based).
const REPORTED: [usize; 6] = [0, 1, 4, 9, 29, 59];

/// The largest difference between two states, relative to the first one's scale.
fn relative_difference(x: &[f32], y: &[f32]) -> f32 {
    let scale = x.iter().fold(1e-3f32, |m, v| m.max(v.abs()));
    x.iter()
        .zip(y)
        .fold(0.0f32, |m, (p, q)| m.max((p - q).abs()))
        / scale
}

fn main() {
    if std::env::args().any(|a| a == "energy") {
        for links in [2usize, 6, 20] {
            for substeps in [5usize, 16] {
                for seed in [3u64, 9] {
                    let (o, fo) = energy::orig::drift(substeps, links, 10.0, seed);
                    let (n, fn_) = energy::new::drift(substeps, links, 10.0, seed);
                    println!(
                        "{links:2} links, {substeps:2} substeps, seed {seed}: worst energy drift \
                         over 10 s: published {:.3} % (finite: {fo}), patched {:.3} % (finite: {fn_})",
                        o * 100.0,
                        n * 100.0
                    );
                }
            }
        }
        return;
    }
    println!(
        "relative difference at steps {:?} (1-based)",
        REPORTED.map(|s| s + 1)
    );
    for limits in [false, true] {
        for seed in [1u64, 7, 42, 1234] {
            let (orig, new) = (a::run(60, seed, limits, 0.0), b::run(60, seed, limits, 0.0));
            let perturbed: Vec<_> = [1e-6f32, -1e-6, 3e-6, -3e-6, 1e-5]
                .iter()
                .map(|&eps| a::run(60, seed, limits, eps))
                .collect();
            let patched: Vec<String> = REPORTED
                .iter()
                .map(|&k| format!("{:.1e}", relative_difference(&orig[k], &new[k])))
                .collect();
            let rounding: Vec<String> = REPORTED
                .iter()
                .map(|&k| {
                    let worst = perturbed
                        .iter()
                        .map(|run| relative_difference(&orig[k], &run[k]))
                        .fold(0.0f32, f32::max);
                    format!("{worst:.1e}")
                })
                .collect();
            println!(
                "seed {seed:4}, limits {limits:5}: patched vs published {}; published vs itself \
                 perturbed {}",
                patched.join(" "),
                rounding.join(" ")
            );
        }
    }
}
