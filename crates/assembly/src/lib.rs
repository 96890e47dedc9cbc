//! Assembly documents: the JSON model of a robot, its validation and its units.
//!
//! This crate owns the document format of the user guide (parts, materials, instances,
//! joints), parses it with serde, and validates it into an [`Assembly`] in SI units
//! (metres, radians, kilograms). Every problem is reported with the JSON path of the
//! offending field and what was expected; a bad document never panics.
//!
//! It knows nothing of physics engines, networking or JSON-RPC: building bodies from an
//! [`Assembly`] is `gymfleet-physics`'s job.

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
    let at_root = path == ".";
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
