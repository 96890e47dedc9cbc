//! Building a [`RobotWorld`] from an [`Assembly`]: bodies, colliders, the multibody tree.

use gymfleet_assembly::{Assembly, DofKind, Joint, JointType, Shape};
use rapier3d::prelude::*;

use crate::actuation::resolve_gains;
use crate::colliders::{assembly_reach, given_mass_properties, insert_body};
use crate::command::{Command, ResolvedGains};
use crate::error::{PhysicsError, Result};
use crate::world::{
    length_unit, BaseValues, FreeRoot, JointDof, JointSlot, PipelineCell, RobotWorld, Sets,
    WorldOptions,
};

/// Gauss–Seidel passes per substep for a world with kinematic loops (Rapier's default, 1,
/// otherwise).
const LOOP_PGS_ITERATIONS: usize = 4;

impl RobotWorld {
    /// Builds the world: one body per instance (the first fixed, the others dynamic),
    /// exact primitive colliders, and every joint as a link of a reduced-coordinate
    /// multibody. Joint damping is exactly the document's (Rapier's default is removed).
    pub fn new(assembly: &Assembly, options: &WorldOptions) -> Result<Self> {
        check_options(options)?;
        let substep_dt = options.substep_dt();
        let mut sets = Sets {
            islands: IslandManager::new(),
            broad_phase: BroadPhaseBvh::new(),
            narrow_phase: NarrowPhase::new(),
            bodies: RigidBodySet::new(),
            colliders: ColliderSet::new(),
            impulse_joints: ImpulseJointSet::new(),
            multibody_joints: MultibodyJointSet::new(),
            soft_bodies: SoftBodySet::new(),
            ccd: CCDSolver::new(),
        };

        let bodies: Vec<RigidBodyHandle> = assembly
            .instances
            .iter()
            .map(|inst| insert_body(&mut sets, inst))
            .collect();
        // Collision detection runs once per step, so contacts must be predicted: soft CCD
        // widens each pair's contact prediction by how far its colliders' points can move in
        // a step (centre-of-mass speed plus spin times radius, capped at the robot's size).
        let reach = assembly_reach(&sets.colliders);
        for &h in &bodies {
            if sets.bodies[h].is_dynamic() {
                sets.bodies[h].set_soft_ccd_prediction(reach);
            }
        }

        let frames = insert_trees(&mut sets, assembly, &bodies)?;

        place_floating_trees(&mut sets);

        // The joints' initial positions, before anything reads the pose (gains, snapshot).
        apply_initial_positions(&mut sets, assembly, &bodies)?;

        set_armatures(&mut sets, assembly, &bodies);

        // The loops' constraints, between bodies the trees now place.
        // Their bodies do not collide.
        let closing =
            crate::loops::add_loop_joints(&mut sets, assembly, &bodies, &frames, |j, f1, f2| {
                generic_joint(j, f1, f2, false)
            });

        let (joints, mut dofs, inertia) =
            joint_slots(&mut sets, assembly, &bodies, &frames, &closing)?;
        let overridden = resolve_gains(&mut dofs, &inertia, options.gains.as_ref())?;
        let gravity = Vector::new(
            assembly.gravity[0] as Real,
            assembly.gravity[1] as Real,
            assembly.gravity[2] as Real,
        );
        crate::action_bound::set_action_bounds(&sets, &joints, &mut dofs, &inertia, gravity);
        let free_roots = free_roots(&sets, &bodies);

        let (params, substep_params) = integration_parameters(assembly, options);

        let n_dofs = dofs.len();
        let base = base_values(assembly, &bodies, &sets, &dofs);
        let fluid = crate::world::FluidDrag::new(assembly, &bodies, &sets);
        let contact_filter = crate::contact_filter::contact_filter(assembly, &bodies, &mut sets);
        let references: Vec<f64> = dofs
            .iter()
            .map(|d| crate::units::to_si(d.kind, d.reference))
            .collect();
        let first_dof: Vec<usize> = joints.iter().map(|j: &JointSlot| j.first_dof).collect();
        let tendons = crate::tendons::tendon_slots(assembly, &first_dof, &references);
        crate::tendons::set_tendon_limits(assembly, &joints, &references, &mut sets)?;
        let mut world = RobotWorld {
            fluid,
            contact_filter,
            tendons,
            initial: std::sync::Arc::new(sets.clone()),
            live: sets,
            pipeline_params: params,
            substep_params,
            substeps: options.substeps,
            gravity,
            bodies,
            joints,
            dofs,
            free_roots,
            floating_base: assembly.floating_base,
            gains: ResolvedGains {
                ball_omega_cap: 0.2 / substep_dt,
                overridden,
            },
            has_ball_joints: assembly.joints.iter().any(|j| j.kind == JointType::Ball),
            command: Command {
                values: vec![0.0; n_dofs],
                ..Command::default()
            },
            pipeline: PipelineCell(PhysicsPipeline::new()),
            base,
        };
        world.reset();
        Ok(world)
    }
}

/// Each joint's slot (its link in a tree, or its loop constraint), its DOFs, and each
/// DOF's apparent inertia (for default gains). Also gives the trees their joint damping,
/// friction, springs, hard limits and self-contacts. Links are looked up only once the
/// trees are complete: insertion may renumber them.
fn joint_slots(
    sets: &mut Sets,
    assembly: &Assembly,
    bodies: &[RigidBodyHandle],
    frames: &[(Pose, Pose)],
    closing: &[Option<ImpulseJointHandle>],
) -> Result<(Vec<JointSlot>, Vec<JointDof>, Vec<f64>)> {
    let mut joints = Vec::with_capacity(assembly.joints.len());
    let mut dofs = Vec::with_capacity(assembly.total_dof());
    let mut inertia = Vec::with_capacity(assembly.total_dof());
    let mut inverse_inertias = std::collections::HashMap::new();
    for (j, joint) in assembly.joints.iter().enumerate() {
        let child = bodies[joint.child];
        if let Some(handle) = closing[j] {
            let link_id = sets.multibody_joints.rigid_body_link(child).copied();
            joints.push(JointSlot {
                kind: joint.kind,
                parent: bodies[joint.parent],
                child,
                // A child in no tree (the ground): no multibody.
                multibody: link_id.map_or(
                    MultibodyIndex(rapier3d::data::Index::from_raw_parts(u32::MAX, u32::MAX)),
                    |l| l.multibody,
                ),
                link: link_id.map_or(0, |l| l.id),
                frame1: frames[j].0,
                first_dof: dofs.len(),
                closing: Some(handle),
                observed_dofs: joint.observed_dof(),
                on_loop: true,
            });
            if joint.observed {
                // Passive: its inertia only feeds default gains, which it never uses.
                inertia.extend(std::iter::repeat_n(0.0, joint.kind.dof()));
                dofs.extend(joint_dofs(j, joint));
            }
            continue;
        }
        let link_id = *sets
            .multibody_joints
            .rigid_body_link(child)
            .ok_or_else(|| PhysicsError::BadOption {
                field: "assembly.joints",
                reason: format!("joint {:?} has no multibody link", joint.name),
            })?;
        let mb = sets
            .multibody_joints
            .get_multibody_mut(link_id.multibody)
            .expect("a link's multibody exists");
        let inv = inverse_inertias
            .entry(link_id.multibody)
            .or_insert_with(|| {
                mb.set_self_contacts_enabled(true);
                // Limits are hard stops: a DOF past its limit is put back on it after
                // every substep (Rapier's own limit engages only once it is past).
                mb.set_hard_limits(true);
                // Rapier gives angular DOFs a default damping of 0.1: remove it, so
                // that a free pendulum keeps its energy unless the document says not.
                mb.damping_mut().fill(0.0);
                mb.dof_inverse_inertia(&sets.bodies)
            })
            .clone();
        let assembly_id = mb.link(link_id.id).expect("link exists").assembly_id();
        // A passive spring (MuJoCo's joint stiffness): Rapier's implicit joint spring on
        // the joint's one free axis (a revolute joint's angle is angular X, a prismatic
        // joint's displacement linear X), its rest measured like the joint's coordinate.
        // The default gains above exclude springs, so setting it here changes nothing
        // for them.
        let spring_axis = match joint.kind {
            JointType::Revolute => Some(3),
            JointType::Prismatic => Some(0),
            _ => None,
        };
        if let (Some(axis), true) = (spring_axis, joint.stiffness > 0.0) {
            if let Some(link) = mb.link_mut(link_id.id) {
                link.joint
                    .set_spring(axis, joint.stiffness as Real, joint.spring_rest as Real);
            }
        }
        for k in 0..joint.kind.dof() {
            mb.damping_mut()[assembly_id + k] = joint.damping as Real;
            mb.frictions_mut()[assembly_id + k] = joint.friction as Real;
            let inv_i = f64::from(inv[assembly_id + k]);
            inertia.push(if inv_i > 0.0 { 1.0 / inv_i } else { 0.0 });
        }
        joints.push(JointSlot {
            kind: joint.kind,
            parent: bodies[joint.parent],
            child,
            multibody: link_id.multibody,
            link: link_id.id,
            frame1: frames[j].0,
            first_dof: dofs.len(),
            closing: None,
            observed_dofs: joint.kind.dof(),
            on_loop: joint.on_loop,
        });
        dofs.extend(joint_dofs(j, joint));
    }
    Ok((joints, dofs, inertia))
}

/// What randomisation scales from: the document's masses, densities, frictions, damping
/// and gains.
fn base_values(
    assembly: &Assembly,
    bodies: &[RigidBodyHandle],
    sets: &Sets,
    dofs: &[JointDof],
) -> BaseValues {
    BaseValues {
        given: assembly
            .instances
            .iter()
            .map(|i| {
                i.inertial
                    .map(|given| given_mass_properties(&given, &i.shape))
            })
            .collect(),
        density: bodies
            .iter()
            .map(|&b| first_collider(&sets, b).map_or(0.0, |c| c.density()))
            .collect(),
        friction: bodies
            .iter()
            .map(|&b| first_collider(&sets, b).map_or(0.0, |c| c.friction()))
            .collect(),
        damping: assembly
            .joints
            .iter()
            .flat_map(|j| std::iter::repeat_n(j.damping as Real, j.observed_dof()))
            .collect(),
        kp: dofs.iter().map(|d| d.kp).collect(),
        kd: dofs.iter().map(|d| d.kd).collect(),
    }
}

/// `options.dt` in (0, 1] s and at least one substep.
fn check_options(options: &WorldOptions) -> Result<()> {
    let dt = options.dt;
    if !(dt.is_finite() && dt > 0.0 && dt <= 1.0) {
        return Err(PhysicsError::BadOption {
            field: "dt",
            reason: format!("expected a step length in (0, 1] s, got {dt}"),
        });
    }
    if options.substeps == 0 {
        return Err(PhysicsError::BadOption {
            field: "substeps",
            reason: "expected at least 1 substep, got 0".to_string(),
        });
    }
    Ok(())
}

/// Inserts every joint that does not close a loop into the multibody trees, parents
/// before children (each insertion appends one link); returns every joint's two frames.
fn insert_trees(
    sets: &mut Sets,
    assembly: &Assembly,
    bodies: &[RigidBodyHandle],
) -> Result<Vec<(Pose, Pose)>> {
    // Parents before children, so each insertion appends one link to a tree.
    let mut order: Vec<usize> = (0..assembly.joints.len()).collect();
    let depth = depths(assembly);
    order.sort_by_key(|&j| depth[assembly.joints[j].child]);
    let mut frames = vec![(Pose::IDENTITY, Pose::IDENTITY); assembly.joints.len()];
    for &j in &order {
        let joint = &assembly.joints[j];
        let (parent, child) = (bodies[joint.parent], bodies[joint.child]);
        let (f1, f2) = joint_frames(&sets.bodies, parent, child, joint);
        frames[j] = (f1, f2);
        if joint.closes_loop {
            continue; // Added once the trees are complete (`loops.rs`).
        }
        // A ground plane collides with what is jointed to it too (MuJoCo never filters
        // the world body's geoms): only the plane stops a link from falling through.
        let contacts = assembly.instances[joint.parent].shape == Shape::Plane;
        let data = generic_joint(joint, f1, f2, contacts);
        sets.multibody_joints
            .insert(parent, child, data, true)
            .ok_or_else(|| PhysicsError::BadOption {
                field: "assembly.joints",
                reason: format!(
                    "joint {:?} could not be added to the multibody tree",
                    joint.name
                ),
            })?;
    }
    Ok(frames)
}

/// Runs forward kinematics once on every tree: one on a dynamic root (a floating base)
/// sits at Rapier's origin until a step reads the root body's pose.
fn place_floating_trees(sets: &mut Sets) {
    // A tree whose root is dynamic (a floating base) starts as Rapier's free root at the
    // origin until a step reads the root body's pose: read it now, so that everything
    // below (initial positions, gains) sees the tree where the document places it.
    let trees: Vec<MultibodyIndex> = sets
        .multibody_joints
        .multibodies()
        .map(|mb| mb.root().rigid_body_handle())
        .filter_map(|root| Some(sets.multibody_joints.rigid_body_link(root)?.multibody))
        .collect();
    for &index in &trees {
        if let Some(mb) = sets.multibody_joints.get_multibody_mut(index) {
            mb.forward_kinematics(&sets.bodies, true);
            mb.update_rigid_bodies(&mut sets.bodies, true);
        }
    }
}

/// Each joint's armature on its DOFs.
fn set_armatures(sets: &mut Sets, assembly: &Assembly, bodies: &[RigidBodyHandle]) {
    // Armature first: the default PD gains below follow each DOF's apparent inertia,
    // which includes it.
    for joint in assembly
        .joints
        .iter()
        .filter(|j| j.armature > 0.0 && !j.closes_loop)
    {
        let link = sets
            .multibody_joints
            .rigid_body_link(bodies[joint.child])
            .copied();
        if let Some(mb) = link.and_then(|l| {
            let mb = sets.multibody_joints.get_multibody_mut(l.multibody)?;
            let first = mb.link(l.id)?.assembly_id();
            Some((mb, first))
        }) {
            let (mb, first) = mb;
            for k in 0..joint.kind.dof() {
                mb.armature_mut()[first + k] = joint.armature as Real;
            }
        }
    }
}

/// The pipeline's parameters for a whole step, and for one substep.
fn integration_parameters(
    assembly: &Assembly,
    options: &WorldOptions,
) -> (IntegrationParameters, IntegrationParameters) {
    // One step is one pipeline step whose solver substeps are the integration substeps:
    // collision detection runs once per step (contacts are speculative, so a contact
    // about to close within the step is still solved at every substep).
    let mut params = IntegrationParameters {
        dt: options.dt as Real,
        length_unit: length_unit(assembly),
        num_solver_iterations: options.substeps as usize,
        // Near rest, products of tiny velocities are subnormal f32s, each operation on
        // which costs ~100 cycles: the seed 6-DOF arm stepped 1.3× slower at rest than
        // swinging. Flushed to zero, identically on every thread.
        flush_denormals: true,
        ..IntegrationParameters::default()
    };
    // Rapier caps body speed at 400 length units per second; with millimetre parts
    // that is a hidden brake. Keep only an absolute, physically meaningless cap.
    params.normalized_max_linear_velocity = 1.0e4 / params.length_unit;
    // Contact softness is a frequency, so a resting body sags by g/ω² whatever its
    // size: 0.3 mm at Rapier's defaults, 7 % of a 4 mm part. Scaling ω by
    // 1/√length_unit keeps the sag relative to the part as Rapier tunes it for metres.
    let stiffen = 1.0 / params.length_unit.sqrt();
    params.contact_softness.natural_frequency *= stiffen;
    params.static_contact_softness.natural_frequency *= stiffen;

    // A loop's constraint couples the bodies of a tree the multibody solves exactly; one
    // Gauss–Seidel pass per substep left a driven four-bar 0.025° off its closed form,
    // four leave it 0.003° off (`crates/env/tests/loops.rs`).
    if assembly.has_loops() {
        params.num_internal_pgs_iterations = LOOP_PGS_ITERATIONS;
    }
    let substep_params = IntegrationParameters {
        dt: options.substep_dt() as Real,
        num_solver_iterations: 1,
        ..params
    };
    (params, substep_params)
}

/// The instances at the root of a tree with a dynamic root (a floating base, or a free
/// body that others are jointed to), in document order: each has six free coordinates
/// that no document joint owns.
fn free_roots(sets: &Sets, bodies: &[RigidBodyHandle]) -> Vec<FreeRoot> {
    bodies
        .iter()
        .enumerate()
        .filter(|&(_, &h)| sets.bodies[h].is_dynamic())
        .filter_map(|(instance, &h)| {
            let link = sets.multibody_joints.rigid_body_link(h)?;
            (link.id == 0).then_some(FreeRoot {
                instance,
                multibody: link.multibody,
            })
        })
        .collect()
}

fn first_collider(sets: &Sets, body: RigidBodyHandle) -> Option<&Collider> {
    let handle = *sets.bodies.get(body)?.colliders().first()?;
    sets.colliders.get(handle)
}

/// Depth of each instance in the joint forest (roots are 0).
fn depths(assembly: &Assembly) -> Vec<usize> {
    let mut parent = vec![None; assembly.instances.len()];
    for joint in assembly.joints.iter().filter(|j| !j.closes_loop) {
        parent[joint.child] = Some(joint.parent);
    }
    (0..assembly.instances.len())
        .map(|mut i| {
            let mut d = 0;
            while let Some(p) = parent[i] {
                d += 1;
                i = p;
                if d > parent.len() {
                    break; // Validation rules out loops; never spin regardless.
                }
            }
            d
        })
        .collect()
}

/// The joint frame (origin at the anchor, X along the axis) in each body's local frame.
fn joint_frames(
    bodies: &RigidBodySet,
    parent: RigidBodyHandle,
    child: RigidBodyHandle,
    joint: &Joint,
) -> (Pose, Pose) {
    let [ax, ay, az] = joint.axis.map(|c| c as Real);
    let [px, py, pz] = joint.anchor.map(|c| c as Real);
    let rotation = Rotation::from_rotation_arc(Vector::X, Vector::new(ax, ay, az).normalize());
    let world = Pose::from_parts(Vector::new(px, py, pz), rotation);
    let f1 = bodies[parent].position().inverse() * world;
    let f2 = bodies[child].position().inverse() * world;
    (f1, f2)
}

/// `contacts`: whether the two instances still collide (a ground plane and what hangs on it).
fn generic_joint(joint: &Joint, f1: Pose, f2: Pose, contacts: bool) -> GenericJoint {
    let locked = match joint.kind {
        JointType::Revolute => JointAxesMask::LOCKED_REVOLUTE_AXES,
        JointType::Prismatic => JointAxesMask::LOCKED_PRISMATIC_AXES,
        JointType::Cylindrical => {
            JointAxesMask::LIN_Y
                | JointAxesMask::LIN_Z
                | JointAxesMask::ANG_Y
                | JointAxesMask::ANG_Z
        }
        JointType::Ball => JointAxesMask::LOCKED_SPHERICAL_AXES,
        JointType::Fixed => JointAxesMask::LOCKED_FIXED_AXES,
    };
    let mut builder = GenericJointBuilder::new(locked)
        .local_frame1(f1)
        .local_frame2(f2)
        .contacts_enabled(contacts);
    if let Some([min, max]) = joint.limits {
        let axis = match joint.kind {
            JointType::Prismatic => JointAxis::LinX,
            _ => JointAxis::AngX,
        };
        builder = builder.limits(axis, [min as Real, max as Real]);
    }
    builder.build()
}

fn joint_dofs(j: usize, joint: &Joint) -> impl Iterator<Item = JointDof> + '_ {
    // As the document wrote them: -120° reads -120, not -119.99999999999999.
    let user_limits = joint.document_limits;
    joint.dof_kinds().iter().map(move |&kind| JointDof {
        joint: j,
        joint_name: joint.name.clone(),
        joint_type: joint.kind,
        kind,
        limits: if kind == DofKind::Linear || joint.kind == JointType::Revolute {
            user_limits
        } else {
            None
        },
        initial: crate::units::from_si(kind, joint.initial),
        max_effort: joint.max_effort,
        gear: joint.gear,
        action_bound: 0.0,
        reference: joint.reference,
        actuated: joint.actuated,
        kp: 0.0,
        kd: 0.0,
    })
}

/// Moves every joint with an `initial` position there (from the document's pose, where
/// the multibodies were built), so that the world's initial state, which every reset
/// restores, starts there; rigid bodies and their colliders follow.
fn apply_initial_positions(
    sets: &mut Sets,
    assembly: &Assembly,
    bodies: &[RigidBodyHandle],
) -> Result<()> {
    let mut touched: Vec<MultibodyIndex> = Vec::new();
    for joint in assembly.joints.iter().filter(|j| j.initial != 0.0) {
        let link = sets
            .multibody_joints
            .rigid_body_link(bodies[joint.child])
            .copied()
            .ok_or_else(|| PhysicsError::BadOption {
                field: "assembly.joints",
                reason: format!("joint {:?} has no multibody link", joint.name),
            })?;
        let Some(mb) = sets.multibody_joints.get_multibody_mut(link.multibody) else {
            continue;
        };
        let Some(first) = mb.link(link.id).map(|l| l.assembly_id()) else {
            continue;
        };
        let mut disp = vec![0.0; mb.ndofs()];
        disp[first] = joint.initial as Real;
        mb.apply_displacements(&disp);
        if !touched.contains(&link.multibody) {
            touched.push(link.multibody);
        }
    }
    if touched.is_empty() {
        return Ok(());
    }
    for index in touched {
        if let Some(mb) = sets.multibody_joints.get_multibody_mut(index) {
            mb.forward_kinematics(&sets.bodies, true);
            mb.update_rigid_bodies(&mut sets.bodies, true);
        }
    }
    // Colliders follow their bodies now, not at the first step: a scene drawn before it
    // shows the robot where it is.
    for (_, co) in sets.colliders.iter_mut() {
        if let Some(parent) = co.parent() {
            let wrt = co.position_wrt_parent().copied().unwrap_or(Pose::IDENTITY);
            co.set_position(*sets.bodies[parent].position() * wrt);
        }
    }
    Ok(())
}
