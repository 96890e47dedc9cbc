//! The parts of a world that other modules build and compute with: the fluid, tendons,
//! actuators, contact rules and the document's values randomisation scales. Kept here so
//! that `world.rs` names them without importing the modules that use them.

use gymfleet_assembly::Dynamics;
use rapier3d::prelude::*;

/// The fluid and the bodies it acts on (`fluid.rs` computes the drag).
#[derive(Debug, Clone)]
pub(crate) struct FluidDrag {
    pub(crate) density: Real,
    pub(crate) viscosity: Real,
    /// Each moving rigid group (instances welded by fixed joints), in document order of
    /// its first instance, which carries the group's force and torque.
    pub(crate) groups: Vec<Vec<RigidBodyHandle>>,
}

/// A point of a spatial tendon's path (`spatial.rs`): where its site is on its body.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PathPoint {
    pub(crate) body: RigidBodyHandle,
    /// The site's point in the body's frame, m.
    pub(crate) local: Vector,
}

/// One heightfield instance and the heights it has now, beside its document's
/// (`terrain.rs`).
#[derive(Debug, Clone)]
pub(crate) struct TerrainSlot {
    pub(crate) instance: usize,
    pub(crate) field: std::sync::Arc<gymfleet_assembly::Heightfield>,
    pub(crate) document: std::sync::Arc<gymfleet_assembly::Heightfield>,
}

/// One tendon as the world uses it (`tendons.rs`, `spatial.rs`).
#[derive(Debug, Clone)]
pub(crate) struct TendonSlot {
    /// A fixed tendon's (DOF index, coefficient).
    pub(crate) dofs: Vec<(usize, f64)>,
    /// A spatial tendon's path (empty for a fixed one).
    pub(crate) path: Vec<PathPoint>,
    pub(crate) stiffness: f64,
    pub(crate) damping: f64,
    /// The spring's rest length (SI).
    pub(crate) rest: f64,
}

/// The body pairs that do not collide, each ordered by handle, sorted and deduplicated,
/// and the collider pairs that always do, with their friction (`contact_filter.rs`: the
/// hook and how the pairs are chosen).
#[derive(Debug, Clone, Default)]
pub(crate) struct ContactFilter {
    pub(crate) excluded: std::sync::Arc<[(RigidBodyHandle, RigidBodyHandle)]>,
    /// The document's explicit pairs, each ordered by handle and sorted, with the pair's
    /// friction (`None`: the colliders' own).
    pub(crate) pairs: std::sync::Arc<[ExplicitPair]>,
}

/// An explicit contact pair: its two colliders, ordered by handle, and its friction
/// (`None`: the colliders' own).
pub(crate) type ExplicitPair = ((ColliderHandle, ColliderHandle), Option<Real>);

/// The document's values domain randomisation scales (`randomize.rs`), kept from the
/// build.
#[derive(Debug, Clone, Default)]
pub(crate) struct BaseValues {
    /// Per instance: its collider's density and friction.
    pub(crate) density: Vec<Real>,
    /// Per instance: its given mass properties (`inertial`), which a mass factor scales
    /// instead of the density.
    pub(crate) given: Vec<Option<MassProperties>>,
    /// Per instance: its collider's exact mass properties where Rapier would weigh an
    /// approximation (an ellipsoid's), which a mass factor scales instead of the density.
    pub(crate) exact: Vec<Option<MassProperties>>,
    pub(crate) friction: Vec<Real>,
    /// Per DOF: the document's damping, and the gains resolved at build.
    pub(crate) damping: Vec<Real>,
    pub(crate) kp: Vec<f64>,
    pub(crate) kd: Vec<f64>,
    pub(crate) kv: Vec<f64>,
}

/// One actuator as the world drives it.
#[derive(Debug, Clone)]
pub(crate) struct ActuatorSlot {
    /// (DOF index, moment): the generalized force per unit of actuator force on each DOF
    /// it moves, which is also the DOF's coefficient in the actuator's length.
    pub(crate) moments: Vec<(usize, f64)>,
    /// An actuator on a spatial tendon: the tendon and the gear (its moments then follow
    /// the path, and `moments` is empty).
    pub(crate) spatial: Option<(usize, f64)>,
    pub(crate) ctrl_range: Option<[f64; 2]>,
    pub(crate) force_range: Option<[f64; 2]>,
    pub(crate) act_range: Option<[f64; 2]>,
    pub(crate) gain: [f64; 3],
    pub(crate) bias: [f64; 3],
    pub(crate) dynamics: Dynamics,
    /// Whether the force changes within a step under a held control.
    pub(crate) state_dependent: bool,
}

/// A step that stopped because its contacts asked for more solver work than the world's
/// limit ([`RobotWorld::set_contact_work_limit`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ContactOverload {
    /// Contact pairs with at least one contact point, as the stopping detection found them.
    pub pairs: usize,
    /// Contact points the solver would have solved.
    pub points: usize,
    /// Solver substeps per step.
    pub substeps: u32,
    /// `points × substeps`: contact point-substeps.
    pub work: usize,
    /// The limit, in contact point-substeps per step.
    pub max: usize,
    /// Substeps the world had already integrated when a later detection stopped it and no
    /// copy was kept; 0: the world is where the last step left it.
    pub substeps_done: u32,
}

/// A copy of the world's sets a substepped step may go back to; clones start empty.
#[derive(Default)]
pub(crate) struct Rollback(pub(crate) Option<Box<(super::Sets, Vec<f64>)>>);

impl Clone for Rollback {
    fn clone(&self) -> Self {
        Rollback(None)
    }
}
