//! The three stages of building a world (`RobotWorld::build` in `build.rs`): the bodies
//! with their colliders and given masses ([`place_bodies`]), the multibody trees, loops and
//! joint slots ([`build_trees`]), and the parts built on them ([`world_parts`]).

use gymfleet_assembly::Assembly;
use rapier3d::prelude::*;

use super::slots::{joint_slots, set_armatures};
use super::trees::{
    apply_initial_positions, fold_owners, generic_joint, held_fixed, insert_trees,
    place_floating_trees, refresh_loop_frames,
};
use super::{planar, rehang, split};
use crate::actuation::resolve_gains;
use crate::colliders::{
    assembly_reach, attach_collider, given_mass_properties, insert_body, instance_pose,
    set_given_masses,
};
use crate::error::Result;
use crate::world::{JointDof, JointSlot, Sets, WorldOptions};

pub(super) fn empty_sets() -> Sets {
    Sets {
        islands: IslandManager::new(),
        broad_phase: BroadPhaseBvh::new(),
        narrow_phase: NarrowPhase::new(),
        bodies: RigidBodySet::new(),
        colliders: ColliderSet::new(),
        impulse_joints: ImpulseJointSet::new(),
        multibody_joints: MultibodyJointSet::new(),
        soft_bodies: SoftBodySet::new(),
        ccd: CCDSolver::new(),
    }
}

/// The bodies of a world being built, with their colliders and given masses
/// ([`place_bodies`]), indexed by instance.
pub(super) struct Placed {
    /// The instances held fixed.
    pub(super) held: Vec<bool>,
    /// The instance whose body each instance is part of (itself, or the one it is folded
    /// into).
    pub(super) owners: Vec<usize>,
    pub(super) roots: Vec<planar::PlanarRoot>,
    pub(super) lanes: Vec<Option<crate::world::Lane>>,
    /// Instances a weld took out of the trees: held fixed on their own, or folded.
    pub(super) welded_away: Vec<bool>,
    pub(super) bodies: Vec<RigidBodyHandle>,
    pub(super) colliders: Vec<ColliderHandle>,
    /// Each instance's frame in its body's.
    pub(super) placements: Vec<Pose>,
    pub(super) given: Vec<Option<MassProperties>>,
    /// Whether an instance's body carries another instance too.
    pub(super) shared: Vec<bool>,
}

/// One body per instance that owns one (the fixed ones fixed, the others dynamic), each
/// instance's collider on its owner's body, and the given masses.
pub(super) fn place_bodies(sets: &mut Sets, assembly: &Assembly) -> Placed {
    let held = held_fixed(assembly);
    let mut owners = fold_owners(assembly, &held);
    // Slide, slide and hinge through two helpers, as one joint: the helpers fold into
    // the body below (`build/planar.rs`).
    let roots = planar::planar_roots(assembly, &held);
    planar::fold_helpers(&roots, &mut owners);
    let lanes = planar::lanes(assembly, &roots);
    let n = assembly.instances.len();
    let welded_away: Vec<bool> = (0..n)
        .map(|i| (held[i] && !assembly.instances[i].grounded) || owners[i] != i)
        .collect();
    let mut bodies = vec![RigidBodyHandle::invalid(); n];
    let mut colliders = vec![ColliderHandle::invalid(); n];
    let mut placements = vec![Pose::IDENTITY; n];
    for i in (0..n).filter(|&i| owners[i] == i) {
        (bodies[i], colliders[i]) = insert_body(sets, &assembly.instances[i], held[i]);
    }
    for i in (0..n).filter(|&i| owners[i] != i) {
        let owner = owners[i];
        placements[i] = instance_pose(&assembly.instances[owner]).inverse()
            * instance_pose(&assembly.instances[i]);
        bodies[i] = bodies[owner];
        colliders[i] = attach_collider(sets, &assembly.instances[i], bodies[i], placements[i]);
    }
    let given: Vec<Option<MassProperties>> = assembly
        .instances
        .iter()
        .map(|i| {
            i.inertial
                .map(|given| given_mass_properties(&given, &i.shape))
        })
        .collect();
    set_given_masses(sets, &bodies, &owners, &placements, &given, false);
    // A body is shared when an instance is folded into it: the folded one and its owner.
    let mut shared = vec![false; n];
    for (i, &owner) in owners.iter().enumerate().filter(|&(i, &o)| o != i) {
        shared[i] = true;
        shared[owner] = true;
    }
    predict_contacts(sets, &bodies);
    Placed {
        held,
        owners,
        roots,
        lanes,
        welded_away,
        bodies,
        colliders,
        placements,
        given,
        shared,
    }
}

/// The multibody trees and loops of a world being built ([`build_trees`]).
pub(super) struct Trees {
    pub(super) joints: Vec<JointSlot>,
    pub(super) dofs: Vec<JointDof>,
    /// Whether the options' gains replaced the defaults.
    pub(super) overridden: bool,
    /// The (child, former parent) instance pairs a rehung or split tree keeps apart.
    pub(super) exclusions: Vec<(usize, usize)>,
    pub(super) gravity: Vector,
}

/// Every joint: the trees (rehung and split where they must be, `rehang.rs`, `split.rs`),
/// placed at their initial positions with their armatures, the loops' constraints, each
/// joint's slot and DOFs, and the DOFs' gains and action bounds.
pub(super) fn build_trees(
    sets: &mut Sets,
    assembly: &Assembly,
    placed: &Placed,
    options: &WorldOptions,
) -> Result<Trees> {
    let (bodies, roots, lanes) = (&placed.bodies, &placed.roots, &placed.lanes);
    let rehung = rehang::rehang_parents(assembly, &placed.held);
    let anchors = split::split_trees(sets, assembly, bodies, &placed.held, roots, &rehung);
    let hung = (&rehung[..], &anchors.of_joint[..]);
    let mut frames = insert_trees(sets, assembly, bodies, &placed.welded_away, roots, hung)?;
    place_floating_trees(sets);
    // The joints' initial positions, before anything reads the pose (gains, snapshot).
    apply_initial_positions(sets, assembly, bodies, lanes)?;
    set_armatures(sets, assembly, bodies, lanes);
    refresh_loop_frames(sets, assembly, bodies, &mut frames);
    // The loops' constraints, between bodies the trees now place.
    // Their bodies do not collide.
    let closing = crate::loops::add_loop_joints(sets, assembly, bodies, &frames, |j, f1, f2| {
        generic_joint(j, f1, f2, false)
    });
    let welded_away = &placed.welded_away;
    let (mut joints, mut dofs, inertia) = joint_slots(
        sets,
        assembly,
        bodies,
        &frames,
        &closing,
        welded_away,
        lanes,
    )?;
    // MuJoCo sizes each compliant contact and limit from its bodies at the model's pose.
    crate::colliders::set_invweights(sets);
    hang_slots(&mut joints, &rehung, &anchors.of_joint, roots, bodies);
    let g = assembly.gravity;
    let gravity = Vector::new(g[0] as Real, g[1] as Real, g[2] as Real);
    let loads = crate::loads::dof_loads(sets, &joints, &dofs, &inertia, gravity);
    let overridden = resolve_gains(&mut dofs, &loads, options.gains.as_ref())?;
    crate::action_bound::set_action_bounds(&joints, &mut dofs, &loads);
    let exclusions = [
        rehang::rehung_exclusions(assembly, &rehung),
        anchors.exclusions,
    ]
    .concat();
    Ok(Trees {
        joints,
        dofs,
        overridden,
        exclusions,
        gravity,
    })
}

/// The parts of a world built on its bodies and trees: its free and mocap bodies, contact
/// filter, tendons (with their limits) and actuators.
pub(super) struct Parts {
    pub(super) free_bodies: Vec<crate::world::BodyRef>,
    pub(super) mocaps: Vec<crate::world::MocapSlot>,
    pub(super) contact_filter: crate::world::ContactFilter,
    pub(super) tendons: Vec<crate::world::TendonSlot>,
    pub(super) actuators: Vec<crate::world::ActuatorSlot>,
}

pub(super) fn world_parts(
    assembly: &Assembly,
    sets: &mut Sets,
    (bodies, colliders, placements): (&[RigidBodyHandle], &[ColliderHandle], &[Pose]),
    trees: &Trees,
) -> Result<Parts> {
    let (joints, dofs, exclusions) = (&trees.joints, &trees.dofs, &trees.exclusions);
    let reference = |instance: usize| crate::world::BodyRef {
        instance,
        frame: assembly.instances[instance]
            .body_frame
            .map(|f| crate::free_bodies::local_pose(f.position, f.rotation)),
    };
    let free_bodies = assembly.free_bodies().into_iter().map(reference).collect();
    let mocaps = assembly
        .mocap_bodies()
        .into_iter()
        .map(|i| crate::world::MocapSlot {
            body: reference(i),
            target: None,
        })
        .collect();
    let contact_filter =
        crate::contact_filter::contact_filter(assembly, bodies, colliders, exclusions, sets);
    let references: Vec<f64> = dofs
        .iter()
        .map(|d| crate::units::to_si(d.kind, d.reference))
        .collect();
    let first_dof: Vec<usize> = joints.iter().map(|j: &JointSlot| j.first_dof).collect();
    let paths: Vec<_> = assembly
        .tendons
        .iter()
        .map(|t| crate::spatial::path_points(assembly, t, bodies, placements))
        .collect();
    crate::tendons::set_tendon_limits(assembly, joints, &references, sets)?;
    crate::spatial::set_path_limits(assembly, &paths, sets)?;
    let tendons = crate::tendons::tendon_slots(assembly, &first_dof, &references, paths, sets);
    let actuators = crate::actuators::actuator_slots(assembly, joints, sets);
    Ok(Parts {
        free_bodies,
        mocaps,
        contact_filter,
        tendons,
        actuators,
    })
}

/// Collision detection runs once per step (where contacts are not MuJoCo's), so contacts
/// must be predicted: soft CCD widens each pair's contact prediction by how far its
/// colliders' points can move in a step (centre-of-mass speed plus spin times radius,
/// capped at the robot's size).
fn predict_contacts(sets: &mut Sets, bodies: &[RigidBodyHandle]) {
    let reach = assembly_reach(&sets.colliders);
    for &h in bodies {
        if sets.bodies[h].is_dynamic() {
            sets.bodies[h].set_soft_ccd_prediction(reach);
        }
    }
}

/// Points each joint slot at the body it hangs from: a rehung joint's new parent, a fused
/// planar root's joints at the fixed instance above the chain, and a split tree's root
/// at its anchor (`split.rs`).
fn hang_slots(
    joints: &mut [JointSlot],
    rehung: &[Option<usize>],
    anchors: &[Option<RigidBodyHandle>],
    roots: &[planar::PlanarRoot],
    bodies: &[RigidBodyHandle],
) {
    for (slot, to) in joints.iter_mut().zip(rehung) {
        if let Some(to) = to {
            slot.parent = bodies[*to];
        }
    }
    for root in roots {
        for &j in &root.joints {
            joints[j].parent = bodies[root.parent];
        }
    }
    for (slot, anchor) in joints.iter_mut().zip(anchors) {
        if let Some(anchor) = anchor {
            slot.parent = *anchor;
        }
    }
}
