//! Assembly documents: the JSON model of a robot, its validation and its units.
//!
//! This crate owns the document format of the user guide (parts, materials, instances,
//! joints), parses it with serde, and validates it into an [`Assembly`] in SI units
//! (metres, radians, kilograms). Every problem is reported with the JSON path of the
//! offending field and what was expected; a bad document never panics.
//!
//! It knows nothing of physics engines, networking or JSON-RPC: building bodies from an
//! [`Assembly`] is `gymfleet-physics`'s job.
//!
//! # Modules
//!
//! - `document.rs` mirrors the JSON one to one, with serde both ways: unknown fields are
//!   rejected when read, and absent options are left out when written, which is how
//!   `gymfleet-import` writes its documents. `document/primitive.rs` is `Primitive`'s
//!   hand-written reader, which keeps each error's JSON path; the other sections' document
//!   types sit beside it
//!   (`document/{actuators,contacts,keyframes,sensors,soft,tendons}.rs`).
//! - `validate.rs` checks a document and converts it to the SI `Assembly` of `model.rs`;
//!   its children `validate/{parts,instances,joints,joint_terms}.rs` check one section
//!   each. It collects *every* problem as an `Issue { path, message }` with the JSON path
//!   (`assembly.joints[1].child: unknown instance "forarm" …`). Joint limits are also kept
//!   as written, so they are reported without a trip through SI. `MM_PER_M` is the one mm↔m
//!   factor. A joint's `gear` and `reference` are checked beside its other quantities.
//! - `topology.rs` chooses the spanning tree Kruskal-style: actuated joints first, then
//!   passive ones, each in document order; unobserved joints (`"observed": false`) are
//!   constraints only and never join it. A joint joins the tree when its child has no
//!   parent yet, is not a root (the first instance, a plane, a fixed instance, a mocap
//!   body) and is not already in one tree with its parent; every world-held instance counts
//!   as one body. Every other joint whose two instances the tree joins closes a kinematic
//!   loop (`Joint::closes_loop`, passive), and the joints on a loop's path are marked
//!   (`Joint::on_loop`: `initial` is refused there, and reset noise skips them). A joint
//!   that is neither (a second parent from another tree, a root as child) is an error.
//! - `mesh.rs`: mesh hulls and decompositions with `parry3d` (Rapier's own geometry crate).
//!   A `mesh` primitive (inline `vertices`, optionally `indices`) is made convex at
//!   validation: one hull, or a V-HACD decomposition into at most `MAX_CONVEX_PARTS` (32)
//!   parts, bounded in vertices and triangles (`Shape::Convex`). The `ellipsoid` primitive
//!   is validated as a volume-matched polyhedron of `ELLIPSOID_RINGS` (16) × 32 points
//!   (`Shape::Ellipsoid { radii, hull }`); physics gives it the exact ellipsoid's mass
//!   properties (`colliders.rs`, `exact_mass_properties`).
//! - `simulation.rs`: the document's `simulation`: gravity, the env step used when a
//!   request leaves `dt` at 0, a still fluid, `magnetic` beside gravity, and how the trees'
//!   velocity terms enter a substep (`Assembly::gravity`, `Assembly::dt`,
//!   `Assembly::fluid`, `Assembly::integrator`).
//! - `contacts.rs`: the document's `contacts`: excluded pairs, and pairs that always
//!   collide with their own friction and `condim` (`Assembly::contacts`; the document types
//!   in `document/contacts.rs`).
//! - `sites.rs`: the document's `sites`, named frames of instances (MJCF sites and body
//!   origins, with their axes) that tasks and end effectors can name (`site:NAME` where an
//!   instance has the same name).
//! - `tendons.rs`: tendons, fixed (joint names and coefficients) or spatial (a path through
//!   sites), with a spring, a damper and a range, checked against the validated joints and
//!   sites (`Assembly::tendons`; the document types in `document/tendons.rs`).
//! - `couplings.rs`: the document's `couplings` (MJCF's joint and tendon equalities), each
//!   written as one linear equation over joint displacements (`Coupling`,
//!   `Assembly::couplings`).
//! - `heightfield.rs`: the heightfield primitive (`Shape::Heightfield`, a ground as a plane
//!   is), its grid checked, and `Heightfield::with_heights` for terrain replaced at run
//!   time.
//! - `actuators.rs`: the document's `actuators`, MuJoCo's shortcuts reduced to one general
//!   form (gain, bias, dynamics, ranges; `Assembly::actuators`), checked against the
//!   validated joints and tendons. A joint an actuator drives is made passive to direct
//!   actions (`Assembly::action_dim` = actuated DOFs + actuators).
//! - `keyframes.rs`: the document's `keyframes` (named initial states: joint positions and
//!   velocities by joint name, a floating base's instance frame, ball joints' rotations,
//!   free bodies' and mocap bodies' poses by instance name, the controls and activations
//!   held at the reset) and `initial_keyframe`, checked against the validated joints
//!   (`Assembly::keyframes`, `Keyframe`, `BaseKey`).
//! - `sensors.rs`: the document's `sensors` (MuJoCo's sensor types; `document/sensors.rs`
//!   beside `SiteDef`), each checked against the one kind of object its type reads, into a
//!   `Sensor` with a `SensorObject` by index (`Assembly::sensors`, `Assembly::sensor_dim`).
//!
//! # The document's extensions
//!
//! What imports need (docs/design.md §6.3) is plain JSON too: the `capsule` primitive, the
//! `mesh` primitive, an instance's `inertial` (mass, centre of mass, inertia tensor,
//! checked to be a physical inertia by `inertia_problem`) and `collision` bits, and a
//! joint's `armature`, passive spring (`stiffness`, `spring_rest`: Rapier's implicit
//! multibody joint spring; a `springdamper` sizes it from the world built once without it,
//! physics' `springdamper.rs`) and dry `friction` (Rapier's multibody joint friction), all
//! set in physics' `build.rs`.
//!
//! Also `floating_base` (`Assembly::floating_base`: the first instance free instead of
//! grounded), a `plane` primitive (a ground, fixed wherever it is listed), a joint's
//! `initial` position (where it starts; positions are measured from the document's pose,
//! and limits must hold the start), and scenes: an instance's `fixed` (static geometry,
//! held wherever it is listed, as a plane is), `mocap` (a kinematic body moved by pose
//! targets) and `body_frame` (the reference frame a free or mocap body is observed by).
//! `Assembly::free_bodies` and `Assembly::mocap_bodies` list them in document order (a free
//! body: unjoined above, moving, not the floating base). MuJoCo's soft constraints: a
//! material's `soft_contact` and a joint's `soft_limit` (`document/soft.rs`, validated in
//! `validate/parts.rs` and `validate/joint_terms.rs` into `model/soft.rs`'s `SoftContact`
//! and `SoftLimit`). `Assembly::source` keeps the document text, for saved states.
//!
//! Dependencies: serde (with `serde_json`, and `serde_path_to_error` for the paths),
//! `thiserror` and `parry3d`.

mod actuators;
mod contacts;
mod couplings;
mod document;
mod error;
mod heightfield;
mod keyframes;
mod mesh;
mod model;
mod sensors;
mod simulation;
mod sites;
mod tendons;
mod topology;
mod validate;

pub use actuators::MAX_ACTUATORS;
pub use contacts::MAX_CONTACT_RULES;
pub use couplings::{Coupling, MAX_COUPLINGS};
pub use document::{
    ActuatorDef, ActuatorKind, AssemblyDef, CollisionDef, ContactExcludeDef, ContactPairDef,
    ContactsDef, ConvexMode, CouplingDef, Document, DynamicsKind, FluidDef, FrameDef, FrictionCone,
    HeightfieldDef, InertiaDef, InertialDef, InstanceDef, Integrator, JointDef, MaterialDef,
    MeshDef, PartDef, Primitive, SensorDef, SensorFrameDef, SensorType, SimulationDef, SiteDef,
    SiteShape, SiteVolumeDef, SoftContactDef, SoftLimitDef, TendonDef, TendonJointDef, Vec3,
};
pub use document::{BaseKeyDef, KeyframeDef};
pub use error::{
    quoted, quoted_list, shown, AssemblyError, Issue, Result, MAX_ECHOED_CHARS, MAX_LISTED_NAMES,
};
pub use heightfield::{Heightfield, MAX_HEIGHTFIELD_POINTS, MAX_HEIGHTFIELD_SIDE};
pub use keyframes::{BaseKey, KeyControl, Keyframe, MAX_KEYFRAMES};
pub use mesh::{
    ConvexParts, ConvexPiece, ELLIPSOID_RINGS, MAX_CONVEX_PARTS, MAX_DECOMPOSED_TRIANGLES,
    MAX_MESH_TRIANGLES, MAX_MESH_VERTICES,
};
pub use model::{
    inertia_problem, Actuator, Assembly, ContactPair, Contacts, DofKind, Dynamics, Fluid, Inertial,
    Instance, Joint, JointType, LocalFrame, Material, Shape, Site, SoftContact, SoftLimit, Tendon,
    Transmission, DEFAULT_DENSITY, DEFAULT_FRICTION, DEFAULT_GRAVITY, DEFAULT_RESTITUTION,
    MM_PER_M,
};
pub use sensors::{Sensor, SensorFrame, SensorObject, MAX_SENSORS};
pub use simulation::{DEFAULT_MAGNETIC, MAX_FLUID_DENSITY, MAX_FLUID_VISCOSITY};
pub use sites::MAX_SITES;
pub use tendons::{MAX_TENDONS, MAX_TENDON_JOINTS};
pub use validate::validate;

/// Parses and validates a document from JSON text.
pub fn parse(json: &str) -> Result<Assembly> {
    let de = &mut serde_json::Deserializer::from_str(json);
    let doc: Document = serde_path_to_error::deserialize(&mut *de).map_err(|err| {
        let path = err.path().to_string();
        malformed(&path, err.into_inner())
    })?;
    // Reject trailing characters after the document, e.g. `{...} x`.
    de.end().map_err(|err| malformed(".", err))?;
    let mut assembly = validate(&doc)?;
    assembly.source = std::sync::Arc::from(json);
    Ok(assembly)
}

/// Turns a serde error into an issue: JSON syntax errors are reported on the whole
/// `document` (with the field they were met in, if any); shape errors on their field.
fn malformed(path: &str, inner: serde_json::Error) -> AssemblyError {
    // An unknown top-level field named `""` has the empty path: it is the document's too.
    let at_root = path == "." || path.is_empty();
    let (path, message) = if inner.is_syntax() || inner.is_eof() {
        // The path serde reached, when it names a field (not `.` or an unknown `?`).
        let near = if at_root || path.contains('?') {
            String::new()
        } else {
            format!(" (in {path})")
        };
        (
            "document".to_string(),
            format!("expected a JSON document: {inner}{near}"),
        )
    } else if at_root {
        ("document".to_string(), inner.to_string())
    } else {
        (path.to_string(), inner.to_string())
    };
    AssemblyError::Malformed {
        issue: Issue::new(path, message),
    }
}

/// Parses and validates a document already held as a JSON value.
pub fn from_value(value: serde_json::Value) -> Result<Assembly> {
    parse(&value.to_string())
}
