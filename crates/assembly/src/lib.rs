//! Assembly documents: the JSON model of a robot, its validation and its units.
//!
//! This crate owns the document format of the user guide (parts, materials, instances,
//! joints), parses it with serde, and validates it into an [`Assembly`] in SI units
//! (metres, radians, kilograms). Every problem is reported with the JSON path of the
//! offending field and what was expected; a bad document never panics.
//!
//! It knows nothing of physics engines, networking or JSON-RPC: building bodies from an
//! [`Assembly`] is `gymfleet-physics`'s job.

mod document;
mod error;
mod model;
mod validate;

pub use document::{
    AssemblyDef, Document, InstanceDef, JointDef, MaterialDef, PartDef, Primitive, Vec3,
};
pub use error::{AssemblyError, Issue, Result};
pub use model::{
    Assembly, DofKind, Instance, Joint, JointType, Material, Shape, DEFAULT_DENSITY,
    DEFAULT_FRICTION, DEFAULT_RESTITUTION, MM_PER_M,
};
pub use validate::validate;

/// Parses and validates a document from JSON text.
pub fn parse(json: &str) -> Result<Assembly> {
    let de = &mut serde_json::Deserializer::from_str(json);
    let doc: Document = serde_path_to_error::deserialize(de).map_err(|err| {
        let path = err.path().to_string();
        let inner = err.into_inner();
        let (path, message) = if inner.is_syntax() || inner.is_eof() || path == "." {
            ("document".to_string(), format!("expected a JSON document: {inner}"))
        } else {
            (path, inner.to_string())
        };
        AssemblyError::Malformed {
            issue: Issue::new(path, message),
        }
    })?;
    validate(&doc)
}

/// Parses and validates a document already held as a JSON value.
pub fn from_value(value: serde_json::Value) -> Result<Assembly> {
    parse(&value.to_string())
}
