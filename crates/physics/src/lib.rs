//! A Rapier world built from a validated [`gymfleet_assembly::Assembly`].
//!
//! This crate owns everything between a document and the rigid-body solver: one body per
//! instance with its exact primitive collider and mass from volume × density, the joint
//! tree as a reduced-coordinate multibody rooted at the grounded instance (or at a
//! floating base, whose pose and velocity it reads out), actuation
//! (real torques and forces, force-based PD motors for position and velocity targets),
//! measured joint state readout in user units, and an exact reset from a snapshot.
//!
//! It knows nothing of episodes, rewards or observation layout (that is `gymfleet-env`),
//! and nothing of threads or networks. Its plain data types ([`DynamicState`], [`Draws`],
//! [`PdGains`], [`ActionMode`]) derive serde for the env's saved states; the format is
//! the env's.
//!
//! Units at this crate's boundary are the user's: degrees and millimetres for joint
//! state and targets, N·m and N for efforts, millimetres for poses. Inside, all is SI.
//!
//! The world is Rapier (`rapier3d` 0.36 as patched in `vendor/rapier3d`, f32) built from an
//! `Assembly`. Each module's own documentation says more; this is the map.
//!
//! # Building the world
//!
//! - `build.rs`: one body per instance (fixed where the world holds it, kinematic for a
//!   mocap body, otherwise dynamic and never sleeping), and every joint as a link of a
//!   reduced-coordinate multibody (parents inserted before children, `build/trees.rs`; each
//!   joint's slot, DOFs and per-DOF damping, friction, springs and armature in
//!   `build/slots.rs`), except welds. An instance welded to a grounded one (transitively,
//!   `held_fixed`: Reacher's arena, a URDF base on its `world` link) is a fixed body of its
//!   own, outside the trees; one welded to a moving one is folded into that one's body
//!   (`fold_owners`: MuJoCo's multi-geom bodies), its collider and given mass placed on it.
//!   Either way a joint that never moves costs no tree link. So an instance is not always a
//!   body: `RobotWorld` keeps each instance's collider, its placement on its body
//!   (`placements`), its owner and its given mass, and every per-instance readout (poses,
//!   centres of mass, points, group inertia, contact wrenches, scene parts, randomisation)
//!   goes through them. The initial positions are applied once here
//!   (`apply_initial_positions`), so the initial state that every reset restores already
//!   holds them; `build/trees.rs::refresh_loop_frames` then re-reads the loop joints'
//!   frames, so a loop stays closed where the document starts it.
//! - `colliders.rs`: exact primitive colliders (a mesh: its convex polyhedron, or a
//!   compound of a decomposition's parts) with mass from volume × density (or, with
//!   `inertial`, a collider of density 0 and the given mass properties on the body), and
//!   collision groups with MuJoCo's rule (`InteractionTestMode::Or`). A material's
//!   `soft_contact` makes its colliders MuJoCo-compliant (`compliance()`, friction combined
//!   by their maximum, each body's `invweight` from MuJoCo's `body_invweight0` at the
//!   model's pose in `set_invweights`). A ground plane is a half-space collider that still
//!   collides with what is jointed to it (MuJoCo never filters the world body).
//! - `build/planar.rs`: a planar root (a slide, a second slide and a hinge chained from a
//!   fixed instance through two helper instances, as the MJCF conversion writes
//!   HalfCheetah's `rootx`, `rootz`, `rooty`) becomes one Rapier joint of three DOFs
//!   (linear X, Z and angular Y of a frame with X the first slide and Y the hinge), whose
//!   matrices Rapier builds by composite bodies as the chain's (vendored PATCHES.md §30 for
//!   `M`, §31 for the velocity terms); the helpers fold into the body below. A world with a
//!   fluid keeps the chain (its drag is per body). Each of the chain's joints keeps its
//!   slot, with a `Lane` (its offset among the fused joint's DOFs and its Rapier axis):
//!   every pass over a slot's DOFs reads `JointSlot::axes`, `coord` and `link_dof`, a saved
//!   state holds each DOF where its own joint would, and the helpers' readouts
//!   (`readout.rs`: `body_frame`, `helper_motion`) and scene parts put them where the chain
//!   would hold them.
//! - `build/rehang.rs`: trees that one coupling or ranged tendon joins but that hang from
//!   different static bodies are hung from one of them (their children still kept from
//!   colliding with their former parents).
//! - `build/split.rs`: the converse: independent trees jointed to one fixed body (Pusher's
//!   arm, object and goal on the table) hang from collider-less anchors of their own, so
//!   that each is a multibody of its own rather than one multibody of all their DOFs.
//! - `build/stages.rs`: the build's stages: the bodies with their colliders and given masses,
//!   the trees, loops and joint slots, and the parts built on them.
//! - `build/params.rs`: the pipeline's parameters and their tuning (see there): tolerances
//!   scaled to the smallest part, stiffened contact softness, Rapier's speed cap lifted,
//!   the compliant solver's switch and sweeps, and the loops' Gauss–Seidel passes.
//! - Armature is set before the default gains are derived from each DOF's apparent inertia.
//!   Rapier's default multibody damping (0.1 on angular DOFs) is zeroed (`build/slots.rs`);
//!   only document damping remains.
//!
//! # One step
//!
//! One env step is one Rapier pipeline step of `dt` whose solver substeps are the
//! `substeps` integration substeps of `dt / substeps`: collision detection runs once per
//! env step, so every dynamic body has soft CCD (contacts predicted from each body's
//! velocity and spin, capped at the robot's size). A world whose efforts depend on the
//! state (`has_state_dependent_efforts`: ball joints under targets, a fluid, a springy or
//! damped tendon, a state-dependent actuator) instead steps one pipeline step per substep
//! and recomputes them before each; so does a world with MuJoCo's compliant contacts (an
//! MJCF geom's), whose contacts MuJoCo detects at every timestep (`steps_by_substep`). After every step `RobotWorld::step` refreshes the
//! links' body velocities from the generalized ones (vendored patch 19), so every velocity
//! read from a body is the step's.
//!
//! - `command.rs`: the motor command state (`ActionMode`, `PdGains` and the gains resolved
//!   per DOF, `Command`), below both `actuation.rs` and `world.rs`.
//! - `units.rs`: the user↔SI conversions of readouts and commands (deg↔rad, mm↔m through
//!   `MM_PER_M`; a ball joint's commands convert in `actuation.rs`), and `Units` (document
//!   or SI), the unit system readouts are written in. Torque-mode values are multiplied by
//!   the DOF's `gear`; observed positions include its `reference`.
//! - `actuation.rs`: torque mode sets each DOF's joint-space (generalized) force; position
//!   and velocity targets use Rapier's force-based motors with gains from what each DOF
//!   drives (`loads.rs`), critically damped at `DEFAULT_PD_FREQUENCY_HZ` (20 Hz); velocity
//!   targets use `kv`, raised above `kd` where the DOF's gravity load would bend them by
//!   more than `GRAVITY_SAG_ANGULAR` (0.05 rad/s) or `GRAVITY_SAG_LINEAR` (5 mm/s); ball
//!   joints use an explicit PD shaped by the child's inertia tensor. `max_effort` clamps
//!   every mode. Passive joints (`"actuated": false`, `JointDof::actuated`) get no effort
//!   and never a motor: `set_command` takes one value per actuated DOF and scatters it,
//!   then one control per actuator.
//! - `loads.rs`: what each DOF drives, at the initial pose: its apparent inertia (the
//!   trees' `1 / diag(M⁻¹)`, MuJoCo's `dof_invweight0`) and the effort that holds it
//!   against gravity, kinematic loops included. Default gains and action bounds read it.
//! - `action_bound.rs`: each actuated DOF's action-space bound (`JointDof::action_bound`,
//!   `JointInfo.action_bounds` on the wire): `max_effort / |gear|`, else `GRAVITY_MULTIPLE`
//!   (2) times the effort that holds what the DOF drives against gravity where gravity
//!   pulls hardest, and at least what gives the DOF's apparent inertia
//!   `FALLBACK_ACCELERATION` (10 rad/s² or m/s²). It shapes clients' action spaces and the
//!   load client's default amplitude; it never clamps an effort.
//! - Hard stops live in Rapier (`Multibody::set_hard_limits`, vendored PATCHES.md):
//!   Rapier's limit constraint engages only once a joint is past its limit, so after every
//!   solver substep a limited DOF found past it is put back on it and its outward velocity
//!   removed by an inelastic impulse through the multibody mass matrix. The stops' impulses
//!   are kept (patch 17): `readout.rs`'s `limit_force` is their mean force over the step,
//!   MuJoCo's `qfrc_constraint` of a limited joint. A joint with a `soft_limit` has
//!   MuJoCo's regularized row instead (patch 44, `build/slots.rs`).
//! - `contact_budget.rs`: the contact work a step may ask of the solver
//!   (`RobotWorld::set_contact_work_limit`: contact points × substeps). The pipeline step
//!   counts its solver contact points after detection (patch 40) and, over the budget,
//!   stops before the solver: `RobotWorld::step` returns a `ContactOverload` and no body
//!   moved. A world whose substeps are pipeline steps of their own keeps a copy of its sets
//!   before a step when its last contacts were past half the budget, and goes back to it
//!   when a later substep is over (`ContactOverload::substeps_done` says when it could not:
//!   the env then needs a reset). `initial_contact_work` estimates the first step's on a
//!   copy, for refusing at creation.
//! - `contact_filter.rs`: MuJoCo's contact exclusions as a Rapier contact-pair hook
//!   (`ContactFilter`, passed to every pipeline step): instances of one rigid group
//!   (`rigid_groups`: welded by fixed joints), and of a group and its parent group (through
//!   groups that collide with nothing: MJCF helpers), never collide, the ground excepted;
//!   the document's excluded pairs never do, and its contact pairs always do (their
//!   colliders carry `PAIR_BIT` in their groups and their own bits in their user data, so
//!   the hook is asked for them, and `modify_solver_contacts` gives them the pair's
//!   friction), except two non-moving bodies.
//! - `fluid.rs`: a document's `simulation.fluid`, MuJoCo's inertia-box model: each moving
//!   rigid group (instances welded by fixed joints, one MuJoCo body) gets the viscous and
//!   quadratic drag of the box with its mass and principal inertia, as the user force and
//!   torque of its first body.
//! - `tendons.rs`: fixed tendons over the DOFs: length and rate (SI, `tendon_state`, which
//!   terms read as `tendon_length`/`tendon_velocity`), and a springy or damped tendon's
//!   pull, coef × (−k·(L − rest) − b·L̇), added to each of its joints' generalized forces
//!   after `apply_efforts` writes the commanded ones. A tendon's range is a hard limit on
//!   the multibody (`set_tendon_limits`, patch 20), enforced after every substep with the
//!   joints' hard stops; so is each coupling, as an equality (`min == max`, patch 42).
//! - `spatial.rs`: spatial tendons through sites: the path's length, its jacobian over the
//!   trees' generalized velocities from the links' body jacobians, its rate `J·q̇` and a
//!   force along it as `Jᵀ·f` (springs, dampers and actuators on it; a site on a free body
//!   outside the trees takes it as a user force, cleared with the fluid's before every
//!   substep, `clear_body_forces`); a ranged one is a rope on its multibody
//!   (`set_path_limits`, patch 42).
//! - `actuators.rs`: the document's actuators over the DOFs (`ActuatorSlot`: each DOF's
//!   moment, gear × the tendon's coefficient), MuJoCo's `mj_fwdActuation`: the force from
//!   the length, the velocity and the clamped control or the activation, added as moment ×
//!   force to each DOF's generalized force after `apply_efforts`. Activations advance after
//!   every substep (`advance_activations`) and are part of `DynamicState`; `dampratio`
//!   becomes a velocity bias from the mass matrix's diagonal at the document's pose (patch
//!   38).
//! - `loops.rs`: kinematic loops. A loop-closing joint is a Rapier impulse joint of its
//!   type (with its limits; spring and damping through a force-based motor) between two
//!   bodies of the trees, added after the multibodies (`add_loop_joints`; one whose child
//!   is fixed is inserted fixed body first, as Rapier solves the other order wrongly). Its
//!   `JointSlot` has `closing: Some(handle)`, and every pass over the tree's joints
//!   (motors, efforts, noise, randomisation, saved coordinates) skips it;
//!   `loop_joint_state` observes it from the bodies' relative pose, and `loop_gaps`
//!   measures how far each loop is open. A loop-closing joint to a mocap body is how MJCF's
//!   mocap welds pull what they hold.
//! - `prefetch.rs`: `RobotWorld::prefetch`, a software-prefetch hint over the memory a step
//!   reads (see there); a batch shard calls it for the next env before stepping the current
//!   one. It changes no bit; its one `unsafe` block (the prefetch intrinsic) is the
//!   workspace's only one. The ranges, `HotRanges`, are `world.rs`'s data.
//!
//! # Reading the state
//!
//! - `readout.rs`: measured joint state from the multibody's generalized coordinates (never
//!   motor targets), body poses at the centre of mass, points and directions given in an
//!   instance's frame (for tasks), and a floating base's pose and velocity (`base_state`).
//! - Floating trees: a tree whose root body is dynamic (the floating base, or a free body
//!   others are jointed to) gets Rapier's free root joint, six DOFs ahead of the document's
//!   (`world.rs`, `FreeRoot`); its pose is its body's (read back at build and at every
//!   step), its velocity is saved in `DynamicState::roots`. Vendored patch 11 makes the
//!   free root turn about its centre of mass.
//! - `free_bodies.rs`: free bodies (dynamic bodies with nothing above them, each the root
//!   of its own tree or alone) observed as MuJoCo's free joint (`FREE_POSE_LEN`,
//!   `FREE_VELOCITY_LEN`: the reference frame's pose, its origin's world velocity and the
//!   angular velocity in its axes), and mocap bodies: kinematic position-based Rapier
//!   bodies whose pose target (`set_mocap_target`) Rapier reaches by the end of the next
//!   step, kept in `DynamicState` and put back at a reset.
//! - `bodies.rs`: body-level quantities as MuJoCo defines them, for a group of instances
//!   about a point (the robot's centre of mass): `group_inertia` (`cinert`),
//!   `group_velocity` (`cvel`), `actuator_force` (`qfrc_actuator`).
//! - `contacts.rs`: `contact_wrenches`, the wrench the step's contacts applied to each
//!   instance (the solver's normal and friction impulses read back from the narrow phase,
//!   over `dt`, torques about a given point): MuJoCo's `cfrc_ext`; `for_each_contact` walks
//!   the same points for the touch sensors.
//! - `sensors.rs`: `sensor_data`, every sensor's reading (MuJoCo's `sensordata`) from the
//!   state: frames from the instances' poses, velocities from each body's, subtrees over
//!   the instances jointed below one, touch from the contacts, force and torque from the
//!   subtree's momentum rate less gravity and contacts, rangefinders by a ray cast through
//!   the broad phase. Accelerations are each body's velocity change over the last step
//!   (`keep_motion` before it; `forget_motion` at resets, loads and states put back). The
//!   sensors resolved against the world (`SensorPlan`, shared by a batch's copies) live in
//!   `world/sensor_plan.rs`.
//! - `scene.rs`: `RobotWorld::scene_parts` and `scene_joints`, collider shapes and world
//!   poses in mm, for pictures. `touching.rs`: `RobotWorld::penetrating`, a collision
//!   detection on a copy.
//!
//! # Resets and states
//!
//! - `world.rs`: `RobotWorld`, the live `Sets` and an `initial` snapshot shared by all
//!   clones (`Arc`); reset clones it into the live sets.
//! - `perturb.rs`: seeded start offsets applied to the generalized coordinates after a
//!   reset, from each joint's `initial` position and clamped into its limits
//!   (`reset_with_offsets`; `perturb_base` moves and spins a floating base as MuJoCo's
//!   free-joint noise does). The env draws them from its own seeded stream.
//! - `set_state.rs`: `RobotWorld::set_joint_state`, MuJoCo's `set_state`: every DOF's
//!   coordinate and velocity and a floating base's state set from values (the readout's
//!   layouts), positions clamped into hard limits and loop or ball joints kept (each a
//!   `StateAdjustment`), then the links' velocities written to their bodies (patch 41) so
//!   that what reads them before the next step reads the new motion.
//!   `RobotWorld::place_base` puts a floating base's instance frame at a keyframe's pose
//!   and velocity (before the reset's offsets and noise, which `perturb_base` adds to it).
//! - `randomize.rs`: an episode's domain-randomisation `Draws` (mass and friction per
//!   instance, damping and gains per joint) applied after a reset, default gains recomputed
//!   from the drawn masses; the env draws them from its seeded stream.
//! - `terrain.rs`: heightfields replaced at run time (`set_heightfield`: the live sets and
//!   the initial copy, so the terrain stays through resets; `DynamicState::terrains`
//!   carries the replaced ones).
//! - `state.rs`: `DynamicState` (joint coordinates and generalized velocities in Rapier's
//!   own `f32`s, every body's motion, free roots' velocities, the held command): read out,
//!   checked field by field (counts, finite and bounded values, limits, unit quaternions,
//!   no command on a passive DOF; `state/check.rs`) and put back exactly after a reset
//!   (patch 10 sets the coordinates).
//!
//! # What `world.rs` does not import
//!
//! `world/parts.rs` holds the data other modules build and compute with (`FluidDrag`,
//! `TendonSlot`, `ActuatorSlot`, `ContactFilter`, `BaseValues`, `ContactOverload` and the
//! `Rollback` cell), `world/sensor_plan.rs` the `SensorPlan`, and `world.rs` the prefetch
//! ranges, so that `world.rs` names them without importing the modules that use them
//! (`contact_budget.rs`, `sensors.rs`, `randomize.rs`, `prefetch.rs`): the crate's modules
//! import each other in no loop.

mod action_bound;
mod actuation;
mod actuators;
mod bodies;
mod build;
mod colliders;
mod command;
mod contact_budget;
mod contact_filter;
mod contacts;
mod error;
mod fluid;
mod free_bodies;
mod loads;
mod loops;
mod perturb;
mod prefetch;
mod randomize;
mod readout;
mod scene;
mod sensors;
mod set_state;
mod spatial;
mod springdamper;
mod state;
mod tendons;
mod terrain;
mod touching;
mod units;
mod world;

pub use action_bound::{FALLBACK_ACCELERATION, GRAVITY_MULTIPLE};
pub use actuation::{GRAVITY_SAG_ANGULAR, GRAVITY_SAG_LINEAR};
pub use bodies::{INERTIA_LEN, VELOCITY_LEN};
pub use command::{ActionMode, PdGains, DEFAULT_PD_FREQUENCY_HZ};
pub use contacts::WRENCH_LEN;
pub use error::{PhysicsError, Result};
pub use free_bodies::{FREE_POSE_LEN, FREE_VELOCITY_LEN};
pub use perturb::BASE_NOISE_LEN;
pub use randomize::Draws;
pub use rapier3d::geometry::ContactLoad;
pub use readout::BASE_STATE_LEN;
pub use scene::{SceneJoint, ScenePart, SceneShape};
pub use set_state::StateAdjustment;
pub use state::{BodyMotion, DynamicState, JointCoords};
pub use units::Units;
pub use world::{ContactOverload, JointDof, RobotWorld, WorldOptions};
