//! Energy drift of a free (no torque, no damping) chain of revolute links swinging under
//! gravity, in each engine.

macro_rules! energy {
    ($m:ident, $r:ident) => {
        pub mod $m {
            use ::$r::prelude::*;

            pub fn drift(substeps: usize, links: usize, seconds: f32, seed: u64) -> (f32, bool) {
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
                for k in 0..=links {
                    let b = if k == 0 {
                        RigidBodyBuilder::fixed()
                    } else {
                        RigidBodyBuilder::dynamic().can_sleep(false)
                    };
                    let h = bodies.insert(
                        b.translation(Vector::new(0.0, 0.0, -0.02 * k as f32))
                            .build(),
                    );
                    let c = ColliderBuilder::cuboid(0.002, 0.002, 0.01)
                        .density(2700.0)
                        .collision_groups(InteractionGroups::none())
                        .build();
                    colliders.insert_with_parent(c, h, &mut bodies);
                    handles.push(h);
                }
                for k in 1..=links {
                    let axis = if k % 2 == 0 { Vector::X } else { Vector::Y };
                    let f1 = Pose::from_parts(
                        Vector::new(0.0, 0.0, -0.01),
                        Rotation::from_rotation_arc(Vector::X, axis),
                    );
                    let f2 = Pose::from_parts(
                        Vector::new(0.0, 0.0, 0.01),
                        Rotation::from_rotation_arc(Vector::X, axis),
                    );
                    let data = GenericJointBuilder::new(JointAxesMask::LOCKED_REVOLUTE_AXES)
                        .local_frame1(f1)
                        .local_frame2(f2)
                        .contacts_enabled(false)
                        .build();
                    mbj.insert(handles[k - 1], handles[k], data, true).unwrap();
                }
                let link = *mbj.rigid_body_link(handles[1]).unwrap();
                let mb = mbj.get_multibody_mut(link.multibody).unwrap();
                mb.damping_mut().fill(0.0);
                mb.forward_kinematics(&bodies, false);
                let n = mb.ndofs();
                let disp: Vec<f32> = (0..n).map(|_| 0.6 * rnd()).collect();
                mb.apply_displacements(&disp);
                mb.forward_kinematics(&bodies, false);
                mb.update_rigid_bodies(&mut bodies, true);
                let energy = |bodies: &RigidBodySet| -> f64 {
                    handles
                        .iter()
                        .skip(1)
                        .map(|&h| {
                            let rb = &bodies[h];
                            let m = rb.mass() as f64;
                            let v = rb.linvel();
                            let w = rb.angvel();
                            let iw = rb.mass_properties().effective_angular_inertia() * w;
                            let z = rb.center_of_mass().z as f64;
                            0.5 * m * (v.length_squared() as f64)
                                + 0.5 * (w.dot(iw) as f64)
                                + m * 9.81 * z
                        })
                        .sum()
                };
                let params = IntegrationParameters {
                    dt: 1.0 / 240.0,
                    num_solver_iterations: substeps,
                    ..IntegrationParameters::default()
                };
                let mut pipeline = PhysicsPipeline::new();
                let (mut islands, mut bp, mut np, mut ij, mut sb, mut ccd) = (
                    IslandManager::new(),
                    BroadPhaseBvh::new(),
                    NarrowPhase::new(),
                    ImpulseJointSet::new(),
                    SoftBodySet::new(),
                    CCDSolver::new(),
                );
                let e0 = energy(&bodies);
                // reference scale: energy swing between top and bottom
                let scale = handles
                    .iter()
                    .skip(1)
                    .map(|&h| bodies[h].mass() as f64 * 9.81 * 0.02 * links as f64)
                    .sum::<f64>();
                let mut worst = 0.0f64;
                let mut finite = true;
                for _ in 0..(seconds * 240.0) as usize {
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
                    let e = energy(&bodies);
                    if !e.is_finite() {
                        finite = false;
                        break;
                    }
                    worst = worst.max((e - e0).abs() / scale);
                }
                (worst as f32, finite)
            }
        }
    };
}
energy!(orig, orig);
energy!(new, new);
