//! The raw document model: exactly the JSON of the user guide plus the *(ext)* fields.
//!
//! These types mirror the wire format one to one (millimetres, degrees). They are
//! deserialised with `serde` and then checked by [`crate::validate`], which turns them
//! into the SI-unit [`crate::Assembly`].

use std::collections::BTreeMap;

use serde::Deserialize;

/// A whole assembly document: part definitions, materials and the assembly itself.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Document {
    /// Part definitions, referenced by instances through their `name`.
    pub parts: Vec<PartDef>,
    /// *(ext)* Named materials, referenced by parts and instances.
    #[serde(default)]
    pub materials: BTreeMap<String, MaterialDef>,
    /// The placed instances and the joints between them.
    pub assembly: AssemblyDef,
}

/// A part: a named primitive shape with an optional material.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PartDef {
    /// The part's name, unique within the document.
    pub name: String,
    /// The part's geometry.
    pub primitive: Primitive,
    /// *(ext)* The name of a material in `materials`.
    #[serde(default)]
    pub material: Option<String>,
}

/// A primitive shape, in millimetres, in the part's local frame.
#[derive(Debug, Clone, Deserialize)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
pub enum Primitive {
    /// A box with one corner at the origin, spanning `[0,x]×[0,y]×[0,z]`.
    Cube {
        /// Edge lengths along local X, Y and Z.
        size: Vec3,
    },
    /// A cylinder whose axis is local Z, spanning `z ∈ [0, height]`.
    Cylinder {
        /// Radius in mm.
        radius: f64,
        /// Height in mm.
        height: f64,
    },
    /// *(ext)* A sphere centred at the origin.
    Sphere {
        /// Radius in mm.
        radius: f64,
    },
}

/// *(ext)* Physical material properties.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialDef {
    /// Density in kg/m³ (default 1000).
    #[serde(default)]
    pub density: Option<f64>,
    /// Coulomb friction coefficient (default 0.5).
    #[serde(default)]
    pub friction: Option<f64>,
    /// Restitution coefficient in [0, 1] (default 0).
    #[serde(default)]
    pub restitution: Option<f64>,
}

/// The assembly: instances of parts and the joints that connect them.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AssemblyDef {
    /// Placed parts. The first one is grounded (fixed to the world).
    pub instances: Vec<InstanceDef>,
    /// Joints between instances.
    #[serde(default)]
    pub joints: Vec<JointDef>,
}

/// A placed copy of a part.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InstanceDef {
    /// The part this instance places.
    pub part: String,
    /// The instance id, unique within the assembly.
    pub name: String,
    /// Translation of the part's local frame, in mm (default origin).
    #[serde(default)]
    pub position: Option<Vec3>,
    /// *(ext)* Rotation in degrees, applied about X, then Y, then Z (default none).
    #[serde(default)]
    pub rotation: Option<Vec3>,
    /// *(ext)* Overrides the part's material.
    #[serde(default)]
    pub material: Option<String>,
}

/// The kind of a joint.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum JointType {
    /// One rotational DOF about `axis`.
    Revolute,
    /// One translational DOF along `axis`.
    Prismatic,
    /// Translation along and rotation about `axis`.
    Cylindrical,
    /// Three rotational DOFs about `anchor`.
    Ball,
    /// No DOF: a rigid connection.
    Fixed,
}

/// A joint between a parent and a child instance.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointDef {
    /// The joint's kind.
    #[serde(rename = "type")]
    pub kind: JointType,
    /// *(ext)* A name for the joint; defaults to the child instance's name.
    #[serde(default)]
    pub name: Option<String>,
    /// The parent instance id.
    pub parent: String,
    /// The child instance id.
    pub child: String,
    /// The joint origin in world mm, in the initial configuration.
    #[serde(default)]
    pub anchor: Option<Vec3>,
    /// The joint axis in world coordinates (normalised on load).
    #[serde(default)]
    pub axis: Option<Vec3>,
    /// Lower limit in deg or mm.
    #[serde(default)]
    pub min: Option<f64>,
    /// Upper limit in deg or mm.
    #[serde(default)]
    pub max: Option<f64>,
    /// *(ext)* Viscous damping per DOF in SI (N·m·s/rad or N·s/m); default 0.
    #[serde(default)]
    pub damping: Option<f64>,
    /// *(ext)* Clamp on the torque (N·m) or force (N) of every action mode.
    #[serde(default)]
    pub max_effort: Option<f64>,
}

/// A 3-vector with named components, as the documents write it.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Vec3 {
    /// X component.
    pub x: f64,
    /// Y component.
    pub y: f64,
    /// Z component.
    pub z: f64,
}

impl Vec3 {
    /// The components as an array.
    pub fn to_array(self) -> [f64; 3] {
        [self.x, self.y, self.z]
    }
}
