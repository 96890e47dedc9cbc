//! The raw document model: exactly the JSON of the user guide plus the *(ext)* fields.
//!
//! These types mirror the wire format one to one (millimetres, degrees). They are
//! deserialised with `serde` and then checked by [`crate::validate`], which turns them
//! into the SI-unit [`crate::Assembly`].

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

mod actuators;
mod contacts;
mod keyframes;
mod primitive;
mod sensors;
mod soft;
mod tendons;

pub use actuators::{ActuatorDef, ActuatorKind, DynamicsKind};
pub use contacts::{ContactExcludeDef, ContactPairDef, ContactsDef};
pub use keyframes::{BaseKeyDef, KeyframeDef};
pub use sensors::{SensorDef, SensorFrameDef, SensorType, SiteDef, SiteShape, SiteVolumeDef};
pub use soft::{FrictionCone, SoftContactDef, SoftLimitDef};
pub use tendons::{CouplingDef, TendonDef, TendonJointDef};

/// A whole assembly document: part definitions, materials and the assembly itself.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Document {
    /// Part definitions, referenced by instances through their `name`.
    pub parts: Vec<PartDef>,
    /// *(ext)* Named materials, referenced by parts and instances.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub materials: BTreeMap<String, MaterialDef>,
    /// The placed instances and the joints between them.
    pub assembly: AssemblyDef,
    /// *(ext)* The world's gravity and the env step the description was made for.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub simulation: Option<SimulationDef>,
    /// *(ext)* Whether the first instance is free (a floating base: a legged robot, a
    /// drone) instead of grounded; default `false`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub floating_base: Option<bool>,
}

/// *(ext)* World settings a description carries (MJCF's `<option gravity timestep>`).
#[derive(Debug, Clone, Copy, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SimulationDef {
    /// Gravity in m/s², world frame; default `{0, 0, -9.81}`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gravity: Option<Vec3>,
    /// The env step in s that requests get when they leave `dt` unset; default 1/240.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dt: Option<f64>,
    /// The fluid the bodies move in (MJCF's `<option density viscosity>`); default none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fluid: Option<FluidDef>,
    /// How the coriolis, centrifugal and gyroscopic forces of the joint trees enter a
    /// substep: `"implicit"` (the default: linearized into the substep, MuJoCo's `implicit`)
    /// or `"euler"` (applied as forces of the substep's start, as MuJoCo's `Euler`
    /// integrator does; MJCF files that use it convert to it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub integrator: Option<Integrator>,
    /// The magnetic field magnetometers read, T, world frame; default MuJoCo's
    /// `{0, -0.5, 0}`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub magnetic: Option<Vec3>,
}

/// *(ext)* How the coriolis, centrifugal and gyroscopic forces of the joint trees enter a
/// substep (`simulation.integrator`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Integrator {
    /// Linearized into the substep's mass matrix (semi-implicit, MuJoCo's `implicit`): stable
    /// for free chains without damping. The default.
    #[default]
    Implicit,
    /// Applied as forces of the substep's start, joint damping and springs still implicit:
    /// MuJoCo's `Euler` integrator. Cheaper per substep.
    Euler,
}

/// *(ext)* A still fluid around every body: MuJoCo's inertia-box drag (each body feels the
/// drag of the box with its mass and principal inertia).
#[derive(Debug, Clone, Copy, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct FluidDef {
    /// Density in kg/m³ (quadratic drag); default 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub density: Option<f64>,
    /// Dynamic viscosity in Pa·s (linear drag); default 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub viscosity: Option<f64>,
}

/// A part: a named primitive shape with an optional material.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PartDef {
    /// The part's name, unique within the document.
    pub name: String,
    /// The part's geometry.
    pub primitive: Primitive,
    /// *(ext)* The name of a material in `materials`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
}

/// A primitive shape, in millimetres, in the part's local frame.
///
/// In JSON it is an object tagged by `type` (`"cube"`, `"cylinder"`, `"sphere"`,
/// `"capsule"`, `"mesh"` or `"plane"`) with
/// the variant's fields beside the tag. Its `Deserialize` is written by hand
/// (`document/primitive.rs`) so that errors inside it keep their exact JSON path, e.g.
/// `parts[0].primitive.size.z`.
#[derive(Debug, Clone, Serialize)]
#[serde(tag = "type", rename_all = "lowercase")]
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
    /// *(ext)* A capsule (a cylinder with hemispherical caps) whose axis is local Z,
    /// spanning `z ∈ [0, height]` caps included.
    Capsule {
        /// Radius in mm.
        radius: f64,
        /// Overall length in mm, caps included: at least `2 × radius`.
        height: f64,
    },
    /// *(ext)* An ellipsoid centred at the origin, its semi-axes along local X, Y and Z (MJCF's
    /// `ellipsoid` geom), simulated as a convex polyhedron with the ellipsoid's volume (so
    /// its mass) within about 1 % of its surface.
    Ellipsoid {
        /// Semi-axes along local X, Y and Z, in mm.
        radii: Vec3,
    },
    /// *(ext)* A triangle mesh, simulated as its convex hull or as a convex decomposition.
    Mesh(MeshDef),
    /// *(ext)* The half-space below the part's local XY plane (its normal is local +Z): a
    /// ground. A plane is always fixed to the world and cannot be a joint's child.
    Plane,
    /// *(ext)* Terrain (MJCF's `hfield`): a grid of `rows × columns` elevations over
    /// `x ∈ [−size.x, size.x]`, `y ∈ [−size.y, size.y]`, each `heights` value (in [0, 1])
    /// times `size.z` above the part's XY plane. Columns run along x; row 0 is at `y =
    /// −size.y` (MuJoCo's `hfield_data` order). A ground, as a plane is.
    Heightfield(HeightfieldDef),
}

/// *(ext)* A heightfield primitive as the document writes it: its grid (`rows`, `columns`,
/// `heights`), or a grayscale PNG `file` of the request's assets that the import step
/// replaces with them (the image's top row at `y = +size.y`, as MuJoCo reads it; its
/// values normalised to [0, 1]).
#[derive(Debug, Clone, Serialize)]
pub struct HeightfieldDef {
    /// Grid rows (along y), at least 2.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rows: Option<u32>,
    /// Grid columns (along x), at least 2.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub columns: Option<u32>,
    /// Half-extents along x and y and the elevation a height of 1 reaches, mm.
    pub size: Vec3,
    /// `rows × columns` heights in [0, 1], row by row; default all 0 (flat).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub heights: Option<Vec<f64>>,
    /// A PNG of the request's assets, instead of the grid.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub file: Option<String>,
}

/// *(ext)* A mesh primitive as the document writes it: inline `vertices` (+ `indices`), or a
/// `file` of the request's assets that the import step replaces with them.
#[derive(Debug, Clone, Default, Serialize)]
pub struct MeshDef {
    /// Vertex positions in mm, in the part's frame.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub vertices: Option<Vec<[f64; 3]>>,
    /// Triangles as three indices into `vertices`; needed for a decomposition.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub indices: Option<Vec<[u32; 3]>>,
    /// How the mesh is made convex; default [`ConvexMode::Hull`].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub convex: Option<ConvexMode>,
    /// A file of the request's assets (STL, OBJ or DAE), resolved before validation.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub file: Option<String>,
    /// Per-axis scale of the file's coordinates into mm (default 1: the file is in mm).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub scale: Option<Vec3>,
}

/// How a mesh becomes the convex shapes the physics engine collides.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ConvexMode {
    /// One convex hull of all the vertices.
    Hull,
    /// Several convex parts found by V-HACD (needs `indices`).
    Decomposition,
}

/// *(ext)* Physical material properties.
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialDef {
    /// Density in kg/m³ (default 1000).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub density: Option<f64>,
    /// Coulomb friction coefficient (default 0.5).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction: Option<f64>,
    /// Restitution coefficient in [0, 1] (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub restitution: Option<f64>,
    /// *(ext)* Compliant contacts as MuJoCo models them (`solref`/`solimp`); absent, this
    /// material's contacts are rigid. `{}` gives MuJoCo's defaults.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub soft_contact: Option<SoftContactDef>,
}

/// The assembly: instances of parts and the joints that connect them.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct AssemblyDef {
    /// Placed parts. The first one is grounded (fixed to the world), unless the document
    /// has a `floating_base`.
    pub instances: Vec<InstanceDef>,
    /// Joints between instances.
    #[serde(default)]
    pub joints: Vec<JointDef>,
    /// *(ext)* Named points of instances (MJCF sites and body origins), for tasks.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub sites: Vec<SiteDef>,
    /// *(ext)* Tendons: named linear combinations of joint positions (MJCF's
    /// `<tendon><fixed>`) or paths through sites (`<tendon><spatial>`), observable,
    /// optionally springy and limited.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub tendons: Vec<TendonDef>,
    /// *(ext)* Couplings (MJCF's `<equality><joint>` and `<equality><tendon>`): a joint's
    /// or fixed tendon's displacement held at a linear function of another's, as a hard
    /// constraint.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub couplings: Vec<CouplingDef>,
    /// *(ext)* Contact rules beside the collision bits (MJCF's `<contact>`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contacts: Option<ContactsDef>,
    /// *(ext)* Actuators (MJCF's `<actuator>`): each takes one control value per action,
    /// after the values of the joints actuated directly.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub actuators: Vec<ActuatorDef>,
    /// *(ext)* Named initial states (MJCF's `<keyframe>`), which a reset may start from.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub keyframes: Vec<KeyframeDef>,
    /// *(ext)* The keyframe every reset starts from unless it names another; default
    /// none (the document's pose, and each joint's `initial`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub initial_keyframe: Option<String>,
    /// *(ext)* Sensors (MJCF's `<sensor>`): named readings of joints, sites and instances.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub sensors: Vec<SensorDef>,
}

/// A placed copy of a part.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct InstanceDef {
    /// The part this instance places.
    pub part: String,
    /// The instance id, unique within the assembly.
    pub name: String,
    /// Translation of the part's local frame, in mm (default origin).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub position: Option<Vec3>,
    /// *(ext)* Rotation in degrees, applied about X, then Y, then Z (default none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rotation: Option<Vec3>,
    /// *(ext)* Overrides the part's material.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
    /// *(ext)* Which other instances it collides with (see [`CollisionDef`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub collision: Option<CollisionDef>,
    /// *(ext)* Mass properties given outright, instead of the shape's volume × density.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inertial: Option<InertialDef>,
    /// *(ext)* Fixed to the world where it is placed: static geometry (a table, a wall, a
    /// bin), as a plane always is. It cannot be a joint's child. Default `false`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fixed: Option<bool>,
    /// *(ext)* A mocap body (MuJoCo's `mocap="true"`): kinematic, moved only by the pose
    /// targets a client sets (with a step, or on their own), pushing what it touches and
    /// pulling what a constraint joins to it (a joint from it with `"observed": false`). It
    /// cannot be a joint's child or the floating base. Default `false`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mocap: Option<bool>,
    /// *(ext)* The frame a free body's observed pose and velocity, and a mocap body's pose
    /// targets, refer to (MuJoCo's body frame, where an MJCF conversion puts it), in the
    /// instance's frame; default the instance's centre of mass, with its axes.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub body_frame: Option<FrameDef>,
}

/// *(ext)* A frame given in another: a position in mm and a rotation in degrees, applied
/// about X, then Y, then Z, as an instance's.
#[derive(Debug, Clone, Copy, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct FrameDef {
    /// The origin, mm; default the other frame's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub position: Option<Vec3>,
    /// The rotation, degrees; default none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rotation: Option<Vec3>,
}

/// *(ext)* An instance's mass properties, as URDF's `<inertial>` and MJCF's `<inertial>`
/// give them.
#[derive(Debug, Clone, Copy, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct InertialDef {
    /// Mass in kg.
    pub mass: f64,
    /// Centre of mass in mm, in the instance's frame; default the shape's centroid.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub center_of_mass: Option<Vec3>,
    /// Inertia tensor about the centre of mass, in kg·m², along the instance's axes;
    /// default the shape's own, for this mass (uniform density).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inertia: Option<InertiaDef>,
}

/// *(ext)* A symmetric inertia tensor's six entries, kg·m².
#[derive(Debug, Clone, Copy, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct InertiaDef {
    /// `Ixx`.
    pub xx: f64,
    /// `Iyy`.
    pub yy: f64,
    /// `Izz`.
    pub zz: f64,
    /// `Ixy`; default 0.
    #[serde(default)]
    pub xy: f64,
    /// `Ixz`; default 0.
    #[serde(default)]
    pub xz: f64,
    /// `Iyz`; default 0.
    #[serde(default)]
    pub yz: f64,
}

/// *(ext)* Collision filter bits (MuJoCo's `contype`/`conaffinity`): two instances not
/// connected by a joint collide when `a.group & b.mask` or `b.group & a.mask` is non-zero.
/// Both default to 1, so by default everything collides; `{"group": 0, "mask": 0}`
/// collides with nothing.
#[derive(Debug, Clone, Copy, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CollisionDef {
    /// The instance's own bits (32 of them); default 1.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub group: Option<u32>,
    /// The bits of the instances it collides with; default 1.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mask: Option<u32>,
}

/// The kind of a joint.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
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
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct JointDef {
    /// The joint's kind.
    #[serde(rename = "type")]
    pub kind: JointType,
    /// *(ext)* A name for the joint; defaults to the child instance's name.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// The parent instance id.
    pub parent: String,
    /// The child instance id.
    pub child: String,
    /// The joint origin in world mm, in the initial configuration.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub anchor: Option<Vec3>,
    /// The joint axis in world coordinates (normalised on load).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub axis: Option<Vec3>,
    /// Lower limit in deg or mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min: Option<f64>,
    /// Upper limit in deg or mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max: Option<f64>,
    /// *(ext)* Viscous damping per DOF in SI (N·m·s/rad or N·s/m); default 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping: Option<f64>,
    /// *(ext)* Clamp on the torque (N·m) or force (N) of every action mode.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_effort: Option<f64>,
    /// *(ext)* `false`: a passive joint, observed but not driven (it takes no action
    /// value and has no motor). Default `true`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub actuated: Option<bool>,
    /// *(ext)* `false`: the joint only keeps a kinematic loop closed (MJCF's
    /// `<equality><connect>`): it adds no position or velocity to observations. Only a
    /// loop-closing joint may be unobserved. Default `true`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub observed: Option<bool>,
    /// *(ext)* Armature (a rotor's reflected inertia, MuJoCo's `armature`): added to the
    /// joint-space inertia of each of the joint's DOFs, in kg·m² (angular) or kg
    /// (linear); default 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub armature: Option<f64>,
    /// *(ext)* Where the joint starts (every reset), in deg or mm from the document's
    /// pose (revolute and prismatic joints); default 0. Observed positions are measured
    /// from the document's pose, so a reset observes this value.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub initial: Option<f64>,
    /// *(ext)* A passive spring (MuJoCo's joint `stiffness`): a torque or force
    /// `-stiffness·(q − spring_rest)` on a revolute or prismatic joint, in N·m/rad or N/m;
    /// default 0 (none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stiffness: Option<f64>,
    /// *(ext)* The spring's rest position, in deg or mm from the document's pose (as
    /// observed positions are); default 0. Needs a `stiffness` or a `springdamper`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spring_rest: Option<f64>,
    /// *(ext)* A spring and a damper by time constant and damping ratio, `[timeconst (s),
    /// dampratio]` (MuJoCo's joint `springdamper`): sized by the DOF's inertia at the
    /// document's pose, `I = 1 / (M⁻¹)ᵢᵢ` (MuJoCo's `dof_invweight0`), as `stiffness = I /
    /// (timeconst² · dampratio²)` and `damping = 2·I / timeconst`, in place of the joint's
    /// `stiffness` and `damping`. Revolute and prismatic joints.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub springdamper: Option<[f64; 2]>,
    /// *(ext)* Dry (Coulomb) friction on each DOF (MuJoCo's `frictionloss`, URDF's
    /// `<dynamics friction>`): the largest torque or force, N·m or N, that resists the
    /// joint's motion; default 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction: Option<f64>,
    /// *(ext)* The motor's gear (MuJoCo's motor `gear`): in torque mode an action value
    /// is a control signal and the joint's torque or force is `gear × value`, clamped to
    /// `max_effort`, so the action's bound is `max_effort / gear`. Default 1 (actions in
    /// N·m or N).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gear: Option<f64>,
    /// *(ext)* The position the joint reports at the document's pose (MuJoCo's joint
    /// `ref`), in deg or mm: added to every observed position. Limits, `initial` and
    /// `spring_rest` stay measured from the document's pose. Default 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reference: Option<f64>,
    /// *(ext)* Compliant limits as MuJoCo models them (`solreflimit`/`solimplimit`): past
    /// `min` or `max` the joint is pushed back like a damped spring instead of stopping
    /// hard. Revolute and prismatic joints with limits; absent, the limits are hard stops.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub soft_limit: Option<SoftLimitDef>,
}

impl InstanceDef {
    /// An instance `name` of part `part` at the part's own frame, every option unset.
    pub fn new(part: impl Into<String>, name: impl Into<String>) -> Self {
        InstanceDef {
            part: part.into(),
            name: name.into(),
            position: None,
            rotation: None,
            material: None,
            collision: None,
            inertial: None,
            fixed: None,
            mocap: None,
            body_frame: None,
        }
    }
}

impl JointDef {
    /// A joint of `kind` from `parent` to `child`, every option unset.
    pub fn new(kind: JointType, parent: impl Into<String>, child: impl Into<String>) -> Self {
        JointDef {
            kind,
            name: None,
            parent: parent.into(),
            child: child.into(),
            anchor: None,
            axis: None,
            min: None,
            max: None,
            damping: None,
            max_effort: None,
            actuated: None,
            observed: None,
            armature: None,
            initial: None,
            stiffness: None,
            spring_rest: None,
            springdamper: None,
            friction: None,
            gear: None,
            reference: None,
            soft_limit: None,
        }
    }
}

impl InertialDef {
    /// A mass alone: the centre of mass and inertia are the shape's.
    pub fn mass(mass: f64) -> Self {
        InertialDef {
            mass,
            center_of_mass: None,
            inertia: None,
        }
    }
}

impl From<[f64; 3]> for Vec3 {
    fn from([x, y, z]: [f64; 3]) -> Self {
        Vec3 { x, y, z }
    }
}

/// A 3-vector with named components, as the documents write it.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
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
