//! The validated assembly in SI units: what the physics layer builds from.
//!
//! Every value here has been checked: lengths are positive and finite, axes are unit
//! vectors, references are indices that exist, and the joints form a forest.

mod actuator;
mod soft;

pub use actuator::{Actuator, Dynamics, Transmission};
pub use soft::{SoftContact, SoftLimit};

/// Millimetres per metre.
pub const MM_PER_M: f64 = 1000.0;

/// Gravity when the document gives none, m/s² (Z up).
pub const DEFAULT_GRAVITY: [f64; 3] = [0.0, 0.0, -9.81];

/// Default density when no material gives one, in kg/m³.
pub const DEFAULT_DENSITY: f64 = 1000.0;
/// Default friction coefficient.
pub const DEFAULT_FRICTION: f64 = 0.5;
/// Default restitution coefficient.
pub const DEFAULT_RESTITUTION: f64 = 0.0;

/// A primitive shape in metres, in the part's local frame (see [`crate::Primitive`]).
#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    /// Box spanning `[0,x]×[0,y]×[0,z]`; `size` holds the edge lengths.
    Cuboid {
        /// Edge lengths in m.
        size: [f64; 3],
    },
    /// Cylinder along local Z, centred on it, spanning `z ∈ [0,height]`.
    Cylinder {
        /// Radius in m.
        radius: f64,
        /// Height in m.
        height: f64,
    },
    /// Sphere centred at the origin.
    Sphere {
        /// Radius in m.
        radius: f64,
    },
    /// Capsule along local Z, centred on it, spanning `z ∈ [0,height]` caps included
    /// (`height ≥ 2·radius`).
    Capsule {
        /// Radius in m.
        radius: f64,
        /// Overall length in m.
        height: f64,
    },
    /// An ellipsoid centred at the origin, semi-axes along X, Y, Z in m, with the convex
    /// polyhedron it is simulated as (`ConvexParts::ellipsoid`: the ellipsoid's volume, so
    /// its mass; its surface and inertia within about 1 %).
    Ellipsoid {
        /// Semi-axes, m.
        radii: [f64; 3],
        /// The polyhedron it is collided as.
        hull: std::sync::Arc<crate::ConvexParts>,
    },
    /// A mesh made convex: its hull, or the parts of its convex decomposition.
    Convex(std::sync::Arc<crate::ConvexParts>),
    /// The half-space `z ≤ 0` of the part's frame (a ground: always grounded).
    Plane,
    /// Terrain over the part's XY plane, centred on its origin (a ground, as a plane).
    Heightfield(std::sync::Arc<crate::Heightfield>),
}

impl Shape {
    /// Volume in m³.
    pub fn volume(&self) -> f64 {
        match *self {
            Shape::Cuboid { size } => size[0] * size[1] * size[2],
            Shape::Cylinder { radius, height } => std::f64::consts::PI * radius * radius * height,
            Shape::Sphere { radius } => 4.0 / 3.0 * std::f64::consts::PI * radius.powi(3),
            Shape::Capsule { radius, height } => {
                std::f64::consts::PI * radius * radius * (height - 2.0 * radius)
                    + 4.0 / 3.0 * std::f64::consts::PI * radius.powi(3)
            }
            Shape::Ellipsoid { radii, .. } => {
                4.0 / 3.0 * std::f64::consts::PI * radii[0] * radii[1] * radii[2]
            }
            Shape::Convex(ref parts) => parts.volume(),
            Shape::Plane | Shape::Heightfield(_) => 0.0,
        }
    }

    /// The centroid in the part's local frame, in m.
    pub fn centroid(&self) -> [f64; 3] {
        match *self {
            Shape::Cuboid { size } => [size[0] / 2.0, size[1] / 2.0, size[2] / 2.0],
            Shape::Cylinder { height, .. } | Shape::Capsule { height, .. } => {
                [0.0, 0.0, height / 2.0]
            }
            Shape::Sphere { .. } | Shape::Ellipsoid { .. } => [0.0, 0.0, 0.0],
            Shape::Convex(ref parts) => parts.centroid(),
            Shape::Plane | Shape::Heightfield(_) => [0.0, 0.0, 0.0],
        }
    }

    /// The smallest extent of the shape (an edge, a diameter or a height), in m; a
    /// plane's is infinite.
    pub fn min_extent(&self) -> f64 {
        match *self {
            Shape::Cuboid { size } => size[0].min(size[1]).min(size[2]),
            Shape::Cylinder { radius, height } => (2.0 * radius).min(height),
            Shape::Sphere { radius } | Shape::Capsule { radius, .. } => 2.0 * radius,
            Shape::Ellipsoid { radii, .. } => 2.0 * radii[0].min(radii[1]).min(radii[2]),
            Shape::Convex(ref parts) => parts.min_extent(),
            Shape::Plane | Shape::Heightfield(_) => f64::INFINITY,
        }
    }

    /// Whether the shape is a ground (a plane or a heightfield): fixed to the world
    /// wherever it is listed, never a joint's child.
    pub fn is_ground(&self) -> bool {
        matches!(self, Shape::Plane | Shape::Heightfield(_))
    }
}

/// Surface and bulk properties of an instance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    /// kg/m³.
    pub density: f64,
    /// Coulomb friction coefficient.
    pub friction: f64,
    /// Restitution in [0, 1].
    pub restitution: f64,
    /// MuJoCo's compliant contact, `None` for rigid contacts.
    pub soft_contact: Option<SoftContact>,
}

impl Default for Material {
    fn default() -> Self {
        Material {
            density: DEFAULT_DENSITY,
            friction: DEFAULT_FRICTION,
            restitution: DEFAULT_RESTITUTION,
            soft_contact: None,
        }
    }
}

/// A placed body.
#[derive(Debug, Clone, PartialEq)]
pub struct Instance {
    /// The instance id.
    pub name: String,
    /// Geometry in the instance's local frame.
    pub shape: Shape,
    /// Material of the body.
    pub material: Material,
    /// Translation of the local frame, in m.
    pub position: [f64; 3],
    /// Rotation of the local frame as Euler angles in radians, applied X, then Y, then Z
    /// (extrinsic, i.e. `R = Rz · Ry · Rx`).
    pub rotation: [f64; 3],
    /// Whether the instance is fixed to the world: the first one unless the assembly has a
    /// floating base, every plane, and every instance marked `fixed`.
    pub grounded: bool,
    /// Collision filter bits `(group, mask)`: instances `a` and `b` collide when
    /// `a.group & b.mask` or `b.group & a.mask` is non-zero (jointed pairs never do).
    pub collision: (u32, u32),
    /// Mass properties given outright; `None`: the shape's volume × the density.
    pub inertial: Option<Inertial>,
    /// Whether it is a mocap body: kinematic, moved by pose targets (never grounded).
    pub mocap: bool,
    /// The frame its observed pose (a free body's) and pose targets (a mocap body's) refer
    /// to, in its own frame; `None`: its centre of mass, with its axes.
    pub body_frame: Option<LocalFrame>,
}

/// A frame given in an instance's frame, SI.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalFrame {
    /// The origin, m.
    pub position: [f64; 3],
    /// The rotation as Euler angles in radians, applied X, then Y, then Z, as an
    /// instance's `rotation`.
    pub rotation: [f64; 3],
}

/// Mass properties given outright (see [`crate::InertialDef`]), in SI.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Inertial {
    /// kg.
    pub mass: f64,
    /// Centre of mass in the instance's frame, m.
    pub center_of_mass: [f64; 3],
    /// Inertia about the centre of mass along the instance's axes, kg·m², row-major;
    /// `None`: the shape's own for this mass.
    pub inertia: Option<[[f64; 3]; 3]>,
}

/// Whether a symmetric 3×3 matrix is positive semi-definite (all principal minors ≥ 0,
/// within a relative tolerance).
fn positive_semi_definite(m: &[[f64; 3]; 3], tolerance: f64) -> bool {
    let det2 = |a: usize, b: usize| m[a][a] * m[b][b] - m[a][b] * m[b][a];
    let det3 = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
        - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    let scale = m[0][0].abs().max(m[1][1].abs()).max(m[2][2].abs());
    (0..3).all(|i| m[i][i] >= -tolerance * scale)
        && [(0, 1), (0, 2), (1, 2)]
            .iter()
            .all(|&(a, b)| det2(a, b) >= -tolerance * scale * scale)
        && det3 >= -tolerance * scale * scale * scale
}

/// Why `inertia` (symmetric, kg·m²) is not the inertia of any body, if it is not: a body's
/// inertia is positive definite and its second moment `tr(I)/2·E − I` is positive
/// semi-definite (the principal moments obey the triangle inequality).
pub fn inertia_problem(inertia: &[[f64; 3]; 3]) -> Option<String> {
    const TOLERANCE: f64 = 1e-9;
    let trace = inertia[0][0] + inertia[1][1] + inertia[2][2];
    let strictly = inertia[0][0] > 0.0 && inertia[1][1] > 0.0 && inertia[2][2] > 0.0;
    if !strictly || !positive_semi_definite(inertia, 0.0) {
        return Some("not positive definite (every principal moment must be > 0)".into());
    }
    let mut second = *inertia;
    for (i, row) in second.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            *v = if i == j { trace / 2.0 } else { 0.0 } - *v;
        }
    }
    (!positive_semi_definite(&second, TOLERANCE)).then(|| {
        "its principal moments break the triangle inequality (each must be at most the \
         sum of the other two): no body has this inertia"
            .into()
    })
}

/// The kind of a validated joint, with its DOF count.
pub use crate::document::JointType;

impl JointType {
    /// Number of degrees of freedom the joint leaves free.
    pub fn dof(self) -> usize {
        match self {
            JointType::Revolute | JointType::Prismatic => 1,
            JointType::Cylindrical => 2,
            JointType::Ball => 3,
            JointType::Fixed => 0,
        }
    }

    /// The lowercase name used in documents.
    pub fn as_str(self) -> &'static str {
        match self {
            JointType::Revolute => "revolute",
            JointType::Prismatic => "prismatic",
            JointType::Cylindrical => "cylindrical",
            JointType::Ball => "ball",
            JointType::Fixed => "fixed",
        }
    }

    /// Whether `min`/`max` limits are meaningful for this joint type.
    pub fn supports_limits(self) -> bool {
        matches!(self, JointType::Revolute | JointType::Prismatic)
    }
}

/// A validated joint, in SI units.
#[derive(Debug, Clone, PartialEq)]
pub struct Joint {
    /// Joint name (the document's `name`, or the child's name).
    pub name: String,
    /// Joint kind.
    pub kind: JointType,
    /// Index of the parent in [`Assembly::instances`].
    pub parent: usize,
    /// Index of the child in [`Assembly::instances`].
    pub child: usize,
    /// Joint origin in world m, in the initial configuration.
    pub anchor: [f64; 3],
    /// Unit axis in world coordinates.
    pub axis: [f64; 3],
    /// Hard limits in rad (revolute) or m (prismatic).
    pub limits: Option<[f64; 2]>,
    /// The same limits as the document wrote them, in deg or mm, so that they can be
    /// reported without a round trip through SI.
    pub document_limits: Option<[f64; 2]>,
    /// Viscous damping per DOF, in N·m·s/rad or N·s/m.
    pub damping: f64,
    /// Clamp on the effort of every action mode, in N·m or N.
    pub max_effort: Option<f64>,
    /// Whether the joint is driven: a passive joint's DOFs are observed but take no
    /// action values.
    pub actuated: bool,
    /// Added to the joint-space inertia of each DOF, in kg·m² or kg.
    pub armature: f64,
    /// Where the joint starts, from the document's pose, in rad or m (0 for joints other
    /// than revolute and prismatic); within `limits`.
    pub initial: f64,
    /// A passive spring's stiffness, N·m/rad or N/m (0: none; revolute and prismatic
    /// joints only).
    pub stiffness: f64,
    /// The spring's rest position from the document's pose, rad or m.
    pub spring_rest: f64,
    /// `[timeconst, dampratio]`: the physics sizes `stiffness` and `damping` from the DOF's
    /// inertia at the document's pose (see [`crate::JointDef::springdamper`]).
    pub springdamper: Option<[f64; 2]>,
    /// Dry friction per DOF, N·m or N (0: none).
    pub friction: f64,
    /// Torque-mode actions are control signals: the effort is `gear ×` the value
    /// (1: actions in N·m or N).
    pub gear: f64,
    /// The position reported at the document's pose, deg or mm as written (added to
    /// observed positions; 0 for joints other than revolute and prismatic).
    pub reference: f64,
    /// Whether the joint closes a kinematic loop: it is not an edge of the spanning tree
    /// (`topology.rs` chooses the tree) but a constraint between two bodies of it, passive.
    pub closes_loop: bool,
    /// Whether its DOFs are observed (`false` only for a loop-closing joint that stands
    /// for an MJCF equality constraint).
    pub observed: bool,
    /// Whether it is on a kinematic loop (it closes one, or it is a tree joint on one's
    /// path): reset noise leaves it alone, so that every reset starts with its loops closed.
    pub on_loop: bool,
    /// MuJoCo's compliant limits, SI (radians or metres); `None`: hard stops.
    pub soft_limit: Option<SoftLimit>,
}

impl Joint {
    /// The DOFs it adds to observations (and to the DOF list): its kind's, or none when
    /// unobserved.
    pub fn observed_dof(&self) -> usize {
        if self.observed {
            self.kind.dof()
        } else {
            0
        }
    }

    /// The DOFs it adds to the multibody trees: none for a loop-closing joint.
    pub fn tree_dof(&self) -> usize {
        if self.closes_loop {
            0
        } else {
            self.kind.dof()
        }
    }
}

/// The kind of one degree of freedom, which fixes its units.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DofKind {
    /// Rotation: observed in degrees, actuated in N·m.
    Angular,
    /// Translation: observed in mm, actuated in N.
    Linear,
}

impl Joint {
    /// The kinds of this joint's DOFs, in observation order.
    pub fn dof_kinds(&self) -> &'static [DofKind] {
        match self.kind {
            JointType::Revolute => &[DofKind::Angular],
            JointType::Prismatic => &[DofKind::Linear],
            JointType::Cylindrical => &[DofKind::Linear, DofKind::Angular],
            JointType::Ball => &[DofKind::Angular, DofKind::Angular, DofKind::Angular],
            JointType::Fixed => &[],
        }
    }
}

/// A named point of an instance (see [`crate::SiteDef`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Site {
    /// The site's name.
    pub name: String,
    /// Index of its instance in [`Assembly::instances`].
    pub instance: usize,
    /// The point in the instance's frame, mm.
    pub point: [f64; 3],
    /// Its axes in the instance's frame: Euler angles in radians, X then Y then Z.
    pub rotation: [f64; 3],
    /// Its volume (shape and MuJoCo's sizes, m), if it has one.
    pub volume: Option<(crate::SiteShape, [f64; 3])>,
}

/// A validated assembly: instances, then joints in document order.
#[derive(Debug, Clone, PartialEq)]
pub struct Assembly {
    /// Bodies, in document order. The first is grounded, or the floating base.
    pub instances: Vec<Instance>,
    /// Joints, in document order.
    pub joints: Vec<Joint>,
    /// The document text this assembly was parsed from ([`crate::parse`]; empty when built
    /// by [`crate::validate`] from a [`crate::Document`]): what a saved env state carries,
    /// so that the state rebuilds its env anywhere.
    pub source: std::sync::Arc<str>,
    /// Gravity, m/s², world frame (the document's `simulation.gravity`, else
    /// [`DEFAULT_GRAVITY`]).
    pub gravity: [f64; 3],
    /// The env step the document asks for (`simulation.dt`), s: what an env gets when its
    /// request leaves `dt` unset.
    pub dt: Option<f64>,
    /// Whether the first instance is free (six DOFs that no action drives, observed as the
    /// base's pose and velocity) instead of grounded.
    pub floating_base: bool,
    /// Named points of instances, in document order.
    pub sites: Vec<Site>,
    /// The still fluid the bodies move in (the document's `simulation.fluid`), if any.
    pub fluid: Option<Fluid>,
    /// How the joint trees' velocity terms enter a substep (the document's
    /// `simulation.integrator`).
    pub integrator: crate::document::Integrator,
    /// Tendons, in document order.
    pub tendons: Vec<Tendon>,
    /// Couplings, in document order.
    pub couplings: Vec<crate::Coupling>,
    /// Contact rules beside the collision bits.
    pub contacts: Contacts,
    /// Actuators, in document order: each takes one action value (its control), after
    /// the values of the joints actuated directly.
    pub actuators: Vec<Actuator>,
    /// Named initial states, in document order.
    pub keyframes: Vec<crate::Keyframe>,
    /// The keyframe resets start from unless they name another (the document's
    /// `initial_keyframe`), by index.
    pub initial_keyframe: Option<usize>,
    /// Sensors, in document order: what [`Assembly::sensor_dim`] floats they report.
    pub sensors: Vec<crate::Sensor>,
    /// The magnetic field magnetometers read, T, world (`simulation.magnetic`).
    pub magnetic: [f64; 3],
}

/// Contact rules (see [`crate::ContactsDef`]), by instance index.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Contacts {
    /// Pairs kept from colliding, `(a, b)` with `a < b`, sorted, without repeats.
    pub exclude: Vec<(usize, usize)>,
    /// Pairs that always collide, in document order.
    pub pairs: Vec<ContactPair>,
}

/// Two instances that always collide (see [`crate::ContactPairDef`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactPair {
    /// One instance (the lower index).
    pub a: usize,
    /// The other.
    pub b: usize,
    /// The pair's friction coefficient (0 for a frictionless pair); `None`: the
    /// instances' own.
    pub friction: Option<f64>,
}

/// A tendon, with an optional spring and damper on it: fixed (length Σ coef · position,
/// SI, positions as observed) or spatial (the length of the path through its sites, m).
#[derive(Debug, Clone, PartialEq)]
pub struct Tendon {
    /// Its name.
    pub name: String,
    /// A fixed tendon's (joint index in document order, coefficient); each joint is
    /// revolute or prismatic. Empty for a spatial tendon.
    pub joints: Vec<(usize, f64)>,
    /// A spatial tendon's path, site indices in [`Assembly::sites`] (two or more). Empty
    /// for a fixed tendon.
    pub sites: Vec<usize>,
    /// Spring stiffness per unit length (N or N·m per m or rad), ≥ 0.
    pub stiffness: f64,
    /// Damping per unit length rate, ≥ 0.
    pub damping: f64,
    /// The spring's rest length; `None`: the length at the document's pose.
    pub spring_length: Option<f64>,
    /// Hard limits on the length, `[min, max]`, if any (a spatial tendon's `min` is ≤ 0:
    /// a rope).
    pub range: Option<[f64; 2]>,
}

impl Tendon {
    /// Whether the tendon is a path through sites (else a combination of joints).
    pub fn is_spatial(&self) -> bool {
        !self.sites.is_empty()
    }
}

/// A still fluid around every body, as MuJoCo's inertia-box model has it: each rigid
/// body (instances welded together count as one) feels the drag of the box that has its
/// mass and principal moments of inertia.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fluid {
    /// Density, kg/m³: drag quadratic in the velocity.
    pub density: f64,
    /// Dynamic viscosity, Pa·s: drag linear in the velocity.
    pub viscosity: f64,
}

impl Assembly {
    /// Index of the site with this name.
    pub fn site_index(&self, name: &str) -> Option<usize> {
        self.sites.iter().position(|s| s.name == name)
    }

    /// Floats all sensors report together (MuJoCo's `nsensordata`).
    pub fn sensor_dim(&self) -> usize {
        self.sensors.iter().map(|s| s.kind.dim()).sum()
    }

    /// Index of the instance with this name.
    pub fn instance_index(&self, name: &str) -> Option<usize> {
        self.instances.iter().position(|i| i.name == name)
    }

    /// Total observed degrees of freedom over all joints, loop-closing ones included
    /// (unobserved ones excluded).
    pub fn total_dof(&self) -> usize {
        self.joints.iter().map(Joint::observed_dof).sum()
    }

    /// Degrees of freedom of the actuated joints: values per action.
    pub fn actuated_dof(&self) -> usize {
        self.joints
            .iter()
            .filter(|j| j.actuated)
            .map(|j| j.kind.dof())
            .sum()
    }

    /// Values per action: one per DOF of the joints actuated directly, then one per
    /// actuator.
    pub fn action_dim(&self) -> usize {
        self.actuated_dof() + self.actuators.len()
    }

    /// Number of tree joints that have at least one DOF (a saved state's joints).
    pub fn num_movable_joints(&self) -> usize {
        self.joints.iter().filter(|j| j.tree_dof() > 0).count()
    }

    /// Whether any joint closes a kinematic loop.
    pub fn has_loops(&self) -> bool {
        self.joints.iter().any(|j| j.closes_loop)
    }

    /// The free bodies, in document order: instances that move freely, joined to nothing
    /// above them (MuJoCo's free joints, the floating base's excepted). Each roots a tree of
    /// its own, made of what is jointed to it; its six free coordinates are observed as
    /// its pose and velocity.
    pub fn free_bodies(&self) -> Vec<usize> {
        let free = free_flags(&self.instances, &self.joints, self.floating_base);
        (0..free.len()).filter(|&i| free[i]).collect()
    }

    /// The mocap bodies (`"mocap": true`), in document order: what a pose target names.
    pub fn mocap_bodies(&self) -> Vec<usize> {
        (0..self.instances.len())
            .filter(|&i| self.instances[i].mocap)
            .collect()
    }
}

/// Which instances are free bodies ([`Assembly::free_bodies`]): hung from no joint, not
/// grounded, not mocap, not the floating base.
pub(crate) fn free_flags(
    instances: &[Instance],
    joints: &[Joint],
    floating_base: bool,
) -> Vec<bool> {
    let mut hangs = vec![false; instances.len()];
    for joint in joints.iter().filter(|j| !j.closes_loop) {
        if let Some(h) = hangs.get_mut(joint.child) {
            *h = true;
        }
    }
    instances
        .iter()
        .enumerate()
        .map(|(i, instance)| {
            let base = i == 0 && floating_base;
            !(hangs[i] || instance.grounded || instance.mocap || base)
        })
        .collect()
}
