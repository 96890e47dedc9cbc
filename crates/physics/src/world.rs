//! [`RobotWorld`]: the live Rapier state of one robot and its snapshot; stepping it is
//! `step.rs`.

use gymfleet_assembly::{DofKind, JointType};
use rapier3d::prelude::*;

use crate::command::{ActionMode, Command, PdGains, ResolvedGains};

mod parts;
mod sensor_plan;
mod step;

pub use parts::ContactOverload;
pub(crate) use parts::{
    ActuatorSlot, BaseValues, ContactFilter, ExplicitPair, FluidDrag, PathPoint, Rollback,
    TendonSlot, TerrainSlot,
};
pub(crate) use sensor_plan::{SensorFrame, SensorObject, SensorPlan, SensorReading};

/// Options for building a world that are not part of the document.
#[derive(Debug, Clone, PartialEq)]
pub struct WorldOptions {
    /// Length of one [`RobotWorld::step`], in seconds.
    pub dt: f64,
    /// Integration substeps per step: each is one semi-implicit Euler step of
    /// `dt / substeps` (one of Rapier's solver substeps).
    pub substeps: u32,
    /// PD gain overrides; `None` derives stable defaults from each DOF's inertia.
    pub gains: Option<PdGains>,
}

impl WorldOptions {
    /// The length of one integration substep, in seconds.
    pub fn substep_dt(&self) -> f64 {
        self.dt / f64::from(self.substeps)
    }
}

impl Default for WorldOptions {
    fn default() -> Self {
        WorldOptions {
            dt: 1.0 / 240.0,
            substeps: 5,
            gains: None,
        }
    }
}

/// One degree of freedom, in observation and action order.
#[derive(Debug, Clone, PartialEq)]
pub struct JointDof {
    /// Index of the owning joint in document order.
    pub joint: usize,
    /// The owning joint's name.
    pub joint_name: String,
    /// The owning joint's type.
    pub joint_type: JointType,
    /// Angular (deg, N·m) or linear (mm, N).
    pub kind: DofKind,
    /// Hard limits in deg or mm, if any.
    pub limits: Option<[f64; 2]>,
    /// Where the DOF starts at every reset, deg or mm from the document's pose.
    pub initial: f64,
    /// Effort clamp in N·m or N, if any.
    pub max_effort: Option<f64>,
    /// Torque-mode action values are control signals: the effort is `gear ×` the value
    /// (1: N·m or N), so the action's bound is `max_effort / |gear|`.
    pub gear: f64,
    /// The bound of a torque-mode action value (effort over `|gear|`): `max_effort / |gear|`
    /// with a `max_effort`, else a default derived from the model (see `action_bound.rs`).
    /// It shapes action spaces only; it never clamps an effort.
    pub action_bound: f64,
    /// The position reported at the document's pose, deg or mm (added to every observed
    /// position; MuJoCo's `ref`).
    pub reference: f64,
    /// Whether the DOF is driven; a passive one is observed but takes no action value.
    pub actuated: bool,
    /// Proportional gain used by position targets, in N·m/rad or N/m.
    pub kp: f64,
    /// Derivative gain used by position targets, in N·m·s/rad or N·s/m.
    pub kd: f64,
    /// Gain used by velocity targets, in N·m·s/rad or N·s/m: `kd` when the gains are given
    /// (`pd_gains.kd`), else at least what keeps the DOF's gravity load from bending a
    /// velocity target by more than 0.05 rad/s (5 mm/s; `actuation.rs`).
    pub kv: f64,
}

/// Everything Rapier mutates while stepping: cloned wholesale to snapshot and reset.
#[derive(Clone)]
pub(crate) struct Sets {
    pub(crate) islands: IslandManager,
    pub(crate) broad_phase: BroadPhaseBvh,
    pub(crate) narrow_phase: NarrowPhase,
    pub(crate) bodies: RigidBodySet,
    pub(crate) colliders: ColliderSet,
    pub(crate) impulse_joints: ImpulseJointSet,
    pub(crate) multibody_joints: MultibodyJointSet,
    pub(crate) soft_bodies: SoftBodySet,
    pub(crate) ccd: CCDSolver,
}

/// A document joint as placed in the multibody.
#[derive(Debug, Clone)]
pub(crate) struct JointSlot {
    pub(crate) kind: JointType,
    pub(crate) parent: RigidBodyHandle,
    pub(crate) child: RigidBodyHandle,
    /// Which multibody and which link of it the child is.
    pub(crate) multibody: MultibodyIndex,
    pub(crate) link: usize,
    /// The joint frame in the parent's local frame (X is the axis); for a fused planar root's
    /// DOF, the fused joint's frame (read a joint's world frame with [`joint_frame`]).
    pub(crate) frame1: Pose,
    /// Index of the joint's first DOF in [`RobotWorld::dofs`].
    pub(crate) first_dof: usize,
    /// A loop-closing joint: its impulse joint between `parent` and `child` (`loops.rs`).
    /// Its `multibody` and `link` are then the child's own tree link, which this joint
    /// does not move: every pass over the tree's joints skips it.
    pub(crate) closing: Option<ImpulseJointHandle>,
    /// How many DOFs it has in [`RobotWorld::dofs`] (0 for an unobserved loop-closing
    /// joint).
    pub(crate) observed_dofs: usize,
    /// On a kinematic loop (closing it or on its path): reset noise leaves it alone.
    pub(crate) on_loop: bool,
    /// Its one DOF's place in a fused planar root (`build/planar.rs`); `None` for a joint
    /// that is its link's whole joint.
    pub(crate) lane: Option<Lane>,
}

/// Where a joint's one DOF sits in a fused joint: its index among that joint's DOFs, and
/// the Rapier axis it moves.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Lane {
    pub(crate) offset: usize,
    pub(crate) axis: JointAxis,
}

/// Rapier's six joint axes, in the order of their `JointAxis` values.
pub(crate) static EVERY_AXIS: [JointAxis; 6] = [
    JointAxis::LinX,
    JointAxis::LinY,
    JointAxis::LinZ,
    JointAxis::AngX,
    JointAxis::AngY,
    JointAxis::AngZ,
];

impl JointSlot {
    /// The joint's DOFs' axes in its link's Rapier joint, in DOF order.
    pub(crate) fn axes(&self) -> &'static [JointAxis] {
        match self.lane {
            None => kind_axes(self.kind),
            Some(lane) => std::slice::from_ref(&EVERY_AXIS[lane.axis as usize]),
        }
    }

    /// Index of the joint's DOF `k` among its multibody's DOFs, given its link's first.
    pub(crate) fn link_dof(&self, link_first: usize, k: usize) -> usize {
        link_first + self.lane.map_or(0, |l| l.offset) + k
    }

    /// Index of the joint's DOF `k` among its link's DOFs (its link velocity's row).
    pub(crate) fn in_link(&self, k: usize) -> usize {
        self.link_dof(0, k)
    }

    /// The coordinate (index into its link joint's six) of the joint's DOF `k`.
    pub(crate) fn coord(&self, k: usize) -> usize {
        self.axes()[k] as usize
    }
}

/// A joint's frame in the world now (origin at its anchor, X along its axis): its parent's
/// pose times its parent-side frame. One DOF of a fused planar root: the root's frame moved
/// by the slides before it, turned so that X is the DOF's own axis (every DOF of the root
/// has the hinge's anchor).
pub(crate) fn joint_frame(sets: &Sets, slot: &JointSlot) -> Pose {
    let frame = *sets.bodies[slot.parent].position() * slot.frame1;
    let Some(lane) = slot.lane else {
        return frame;
    };
    let link = sets
        .multibody_joints
        .get_multibody(slot.multibody)
        .and_then(|mb| mb.link(slot.link));
    let coords = link.map_or([0.0; 6], |l| l.joint().coords());
    let turn = match lane.axis {
        JointAxis::LinZ => Rotation::from_rotation_arc(Vector::X, Vector::Z),
        JointAxis::AngY => Rotation::from_rotation_arc(Vector::X, Vector::Y),
        _ => Rotation::IDENTITY,
    };
    frame * Pose::from_parts(planar_slides(&coords, lane.offset), turn)
}

/// Where the first `slides` of a fused planar root's slides (linear X, then Z) have moved
/// its frame's origin, in that frame: `coords` are the fused joint's six coordinates.
pub(crate) fn planar_slides(coords: &[Real; 6], slides: usize) -> Vector {
    let slid = |k: usize| if slides > k { coords[2 * k] } else { 0.0 };
    Vector::new(slid(0), 0.0, slid(1))
}

/// A joint kind's free axes in its own Rapier joint, in DOF order (linear, then angular).
pub(crate) fn kind_axes(kind: JointType) -> &'static [JointAxis] {
    match kind {
        JointType::Revolute => &[JointAxis::AngX],
        JointType::Prismatic => &[JointAxis::LinX],
        JointType::Cylindrical => &[JointAxis::LinX, JointAxis::AngX],
        JointType::Ball => &[JointAxis::AngX, JointAxis::AngY, JointAxis::AngZ],
        JointType::Fixed => &[],
    }
}

/// A helper instance of a fused planar root (`build/planar.rs`): folded into the body the
/// root moves, yet read out where the chain would hold it, moved by the slides above it
/// and turned by nothing.
#[derive(Debug, Clone)]
pub(crate) struct PlanarHelper {
    pub(crate) instance: usize,
    /// The slot of the root's first slide (its link holds the fused joint).
    pub(crate) slot: usize,
    /// How many of the root's slides move it: 1 or 2.
    pub(crate) slides: usize,
    /// The fused joint's frame in the world (its parent is held fixed).
    pub(crate) frame: Pose,
    /// The helper's frame in the joint frame at the document's pose.
    pub(crate) rest: Pose,
}

/// The root of a kinematic tree whose root body is dynamic: Rapier gives it a free joint
/// of six DOFs (linear, then angular velocity, world frame) ahead of the tree's joints,
/// which no document joint owns. Its pose is its body's.
#[derive(Debug, Clone, Copy)]
pub(crate) struct FreeRoot {
    /// The root's instance.
    pub(crate) instance: usize,
    pub(crate) multibody: MultibodyIndex,
}

/// A free or mocap body as the world reads and moves it (`free_bodies.rs`).
#[derive(Debug, Clone, Copy)]
pub(crate) struct BodyRef {
    /// Its instance.
    pub(crate) instance: usize,
    /// Its reference frame in the instance's frame; `None`: the instance's centre of mass,
    /// with the instance's axes.
    pub(crate) frame: Option<Pose>,
}

/// A mocap body: its instance and frame, and the target its next steps move it to.
#[derive(Debug, Clone, Copy)]
pub(crate) struct MocapSlot {
    pub(crate) body: BodyRef,
    /// Where the instance's body is to be (world, SI), once a target was set; `None`:
    /// where the document put it.
    pub(crate) target: Option<Pose>,
}

/// The physics of one robot: a Rapier world built from an assembly.
///
/// `Clone` gives an independent copy (for batches), sharing nothing.
#[derive(Clone)]
pub struct RobotWorld {
    pub(crate) live: Sets,
    /// The state at creation, shared by every clone of this world (a batch's envs),
    /// so that each env holds one copy of the Rapier sets, not two.
    pub(crate) initial: std::sync::Arc<Sets>,
    /// One step: `dt` integrated as `substeps` of Rapier's solver substeps.
    pub(crate) pipeline_params: IntegrationParameters,
    /// One substep as a pipeline step of its own, for the explicit ball-joint PD, which must
    /// be recomputed every substep (see [`RobotWorld::step`]).
    pub(crate) substep_params: IntegrationParameters,
    pub(crate) substeps: u32,
    /// Whether an instance with MuJoCo's compliant contacts (an MJCF geom's) can touch
    /// another: contacts are then detected at every substep, as MuJoCo detects them at
    /// every timestep (see [`RobotWorld::step`]).
    pub(crate) soft_contacts: bool,
    pub(crate) gravity: Vector,
    /// Each instance's body, in document order. An instance welded to a moving one
    /// shares that one's body (see `owners`).
    pub(crate) bodies: Vec<RigidBodyHandle>,
    /// Each instance's collider (an instance has exactly one), in document order.
    pub(crate) colliders: Vec<ColliderHandle>,
    /// Each instance's frame in its body's frame: the identity for an instance with a body
    /// of its own; a folded instance's placement on the body it was welded into.
    pub(crate) placements: Vec<Pose>,
    /// The instance whose body each instance is part of: itself, or for an instance welded
    /// to a moving one, the first of its weld chain (`build/trees.rs`, `fold_owners`).
    pub(crate) owners: Vec<usize>,
    /// Whether an instance's body carries other instances' colliders too (it owns a
    /// folded one, or is folded): its own mass is then not its body's.
    pub(crate) shared: Vec<bool>,
    /// Each instance's given mass properties (`inertial`) as now scaled by randomisation,
    /// in its own frame.
    pub(crate) given_now: Vec<Option<MassProperties>>,
    /// For an instance on a shared body: its own mass properties in the body's frame (its
    /// collider's and its given ones), kept up to date by randomisation; terms read them
    /// every step.
    pub(crate) own_props: Vec<MassProperties>,
    pub(crate) joints: Vec<JointSlot>,
    pub(crate) dofs: Vec<JointDof>,
    /// Trees with a dynamic root, in document order of their roots.
    pub(crate) free_roots: Vec<FreeRoot>,
    /// The free bodies (`Assembly::free_bodies`), observed as their pose and velocity
    /// (`free_bodies.rs`).
    pub(crate) free_bodies: Vec<BodyRef>,
    /// The mocap bodies, in document order, and their targets (`free_bodies.rs`).
    pub(crate) mocaps: Vec<MocapSlot>,
    /// Whether the first instance is a floating base (see [`RobotWorld::base_state`]).
    pub(crate) floating_base: bool,
    pub(crate) gains: ResolvedGains,
    /// Whether any joint is a ball joint (whose target modes use an explicit PD).
    pub(crate) has_ball_joints: bool,
    pub(crate) command: Command,
    pub(crate) pipeline: PipelineCell,
    /// The document's values that domain randomisation scales.
    pub(crate) base: BaseValues,
    /// The fluid's drag, when the document has a fluid (`fluid.rs`).
    pub(crate) fluid: Option<FluidDrag>,
    /// Tendons, in document order (`tendons.rs`); heightfields (`terrain.rs`).
    pub(crate) tendons: Vec<TendonSlot>,
    pub(crate) terrains: Vec<TerrainSlot>,
    /// Actuators, in document order (`actuators.rs`).
    pub(crate) actuators: Vec<ActuatorSlot>,
    /// Each actuator's activation (0 for one without dynamics); 0 at every reset.
    pub(crate) activations: Vec<f64>,
    /// The body pairs kept from colliding (`contact_filter.rs`).
    pub(crate) contact_filter: ContactFilter,
    /// The helper instances of fused planar roots (`build/planar.rs`).
    pub(crate) planar_helpers: Vec<PlanarHelper>,
    /// Where the state a step reads lies, for [`RobotWorld::prefetch`] (`prefetch.rs`).
    pub(crate) hot: HotRanges,
    /// Contact point-substeps a step may ask for, 0: no limit (`contact_budget.rs`).
    pub(crate) contact_work_limit: usize,
    /// The copy a substepped step near its contact budget may go back to.
    pub(crate) rollback: Rollback,
    /// The sensors, resolved (`sensors.rs`).
    pub(crate) sensor_plan: std::sync::Arc<SensorPlan>,
    /// Each instance's body velocity (linear, angular) before the last step, when a sensor
    /// reads accelerations; empty after a reset.
    pub(crate) motion: Vec<[Real; 6]>,
}

/// The memory ranges a world's step reads, as `(first cache line, lines)`, the steps since
/// they were taken, and whether anyone asked to prefetch them (`prefetch.rs` takes and uses
/// them; a world nobody prefetches never takes them).
#[derive(Debug, Default)]
pub(crate) struct HotRanges {
    pub(crate) ranges: Vec<(usize, usize)>,
    pub(crate) age: u32,
    pub(crate) wanted: std::sync::atomic::AtomicBool,
}

/// A clone's storage is elsewhere: it starts with no ranges, and takes its own after its
/// first step once it is prefetched.
impl Clone for HotRanges {
    fn clone(&self) -> Self {
        Self::default()
    }
}

/// The solver pipeline holds only scratch buffers, so a clone starts a fresh one.
pub(crate) struct PipelineCell(pub(crate) PhysicsPipeline);

impl Clone for PipelineCell {
    fn clone(&self) -> Self {
        PipelineCell(PhysicsPipeline::new())
    }
}

impl RobotWorld {
    /// The degrees of freedom, in document joint order.
    pub fn dofs(&self) -> &[JointDof] {
        &self.dofs
    }

    /// Number of instances (bodies).
    pub fn num_bodies(&self) -> usize {
        self.bodies.len()
    }

    /// The mass of everything that moves, kg: every dynamic body (neither fixed to the world
    /// nor a mocap body), folded instances and helpers included, as the document's masses
    /// (before randomisation) make them.
    pub fn moving_mass(&self) -> f64 {
        // A body's mass is Rapier's after a step; before, computed here on a copy.
        self.initial
            .bodies
            .iter()
            .filter(|(_, rb)| rb.is_dynamic())
            .map(|(_, rb)| {
                let mut rb = rb.clone();
                rb.recompute_mass_properties_from_colliders(&self.initial.colliders);
                f64::from(rb.mass())
            })
            .sum()
    }

    /// Number of joints, fixed ones included (document order).
    pub fn num_joints(&self) -> usize {
        self.joints.len()
    }

    /// The step length in seconds.
    pub fn dt(&self) -> f64 {
        f64::from(self.pipeline_params.dt)
    }

    /// Integration substeps per step.
    pub fn substeps(&self) -> u32 {
        self.substeps
    }

    /// Sets the command held until the next call: efforts in N·m/N (times each DOF's
    /// gear), or targets in deg/mm (position, as observed: with the joint's reference) or
    /// deg/s, mm/s (velocity). `values` has one entry per actuated
    /// DOF, in DOF order (passive DOFs get no effort and no motor), then one control per
    /// actuator (MuJoCo's `ctrl`, whatever the mode).
    ///
    /// The caller validates length and finiteness; this only clamps and converts.
    pub fn set_command(&mut self, mode: ActionMode, values: &[f32]) {
        debug_assert_eq!(values.len(), self.action_dim());
        self.command.mode = mode;
        let direct = values.len() - self.actuators.len().min(values.len());
        self.command.controls.copy_from_slice(&values[direct..]);
        let mut values = values[..direct].iter();
        for (slot, dof) in self.command.values.iter_mut().zip(&self.dofs) {
            *slot = if dof.actuated {
                let value = values.next().copied().unwrap_or(0.0);
                // Position targets are observed positions: the reference is taken off.
                if mode == ActionMode::Position && dof.reference != 0.0 {
                    (f64::from(value) - dof.reference) as f32
                } else {
                    value
                }
            } else {
                0.0
            };
        }
        self.configure_motors();
    }

    /// DOFs that take an action value.
    pub fn actuated_dofs(&self) -> usize {
        self.dofs.iter().filter(|d| d.actuated).count()
    }

    /// Values per action: the actuated DOFs', then one control per actuator.
    pub fn action_dim(&self) -> usize {
        self.actuated_dofs() + self.actuators.len()
    }

    /// Restores the initial state exactly: poses, velocities, contacts and solver caches.
    /// The command is reset to zero torque.
    pub fn reset(&mut self) {
        self.live.clone_from(&self.initial);
        self.forget_motion();
        // The clone may have moved the sets' storage: the next step takes the ranges again.
        self.hot.ranges.clear();
        for mocap in &mut self.mocaps {
            mocap.target = None;
        }
        self.command.mode = ActionMode::Torque;
        self.command.values.iter_mut().for_each(|v| *v = 0.0);
        self.command.controls.iter_mut().for_each(|v| *v = 0.0);
        self.activations.iter_mut().for_each(|a| *a = 0.0);
        self.configure_motors();
    }

    pub(crate) fn joint_frame_world(&self, slot: &JointSlot) -> Pose {
        joint_frame(&self.live, slot)
    }

    /// Whether every body pose and velocity is finite.
    pub fn is_finite(&self) -> bool {
        self.bodies.iter().all(|&h| {
            let rb = &self.live.bodies[h];
            rb.position().is_finite() && rb.linvel().is_finite() && rb.angvel().is_finite()
        })
    }
}

/// The characteristic length used for Rapier's tolerances: the smallest extent of
/// any part, so that a 4 mm part gets micrometre-scale slop rather than 5 mm.
pub(crate) fn length_unit(assembly: &gymfleet_assembly::Assembly) -> f32 {
    let smallest = assembly
        .instances
        .iter()
        .map(|i| i.shape.min_extent())
        .fold(f64::INFINITY, f64::min);
    smallest.clamp(1e-4, 1.0) as f32
}
