//! *(ext)* Sites (named points of instances) and sensors: named readings of joints,
//! actuators, tendons, sites and instances, as MJCF's `<sensor>` defines them.

use serde::{Deserialize, Serialize};

use super::Vec3;

/// *(ext)* A named point of an instance, which moves with it.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SiteDef {
    /// The site's name (unique among sites).
    pub name: String,
    /// The instance it belongs to.
    pub instance: String,
    /// The point, mm in the instance's frame (the frame its placement defines).
    pub point: Vec3,
    /// The site's axes in the instance's frame, degrees about X, then Y, then Z (as an
    /// instance's `rotation`); default the instance's axes. An end effector that names
    /// the site is observed with them.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rotation: Option<Vec3>,
    /// The site's volume, in its own axes (MJCF's site `type` and `size`): a touch sensor
    /// on the site counts only the contacts inside it. Default none: every contact on the
    /// site's body.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub volume: Option<SiteVolumeDef>,
}

/// *(ext)* A site's volume, centred on the site, MuJoCo's site shapes and sizes (mm).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SiteVolumeDef {
    /// Its shape.
    #[serde(rename = "type")]
    pub kind: SiteShape,
    /// MuJoCo's sizes: a sphere's radius (`x`); a capsule's or cylinder's radius (`x`) and
    /// half-length along the site's z (`y`); an ellipsoid's radii; a box's half-sizes.
    pub size: Vec3,
}

/// A site volume's shape.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum SiteShape {
    /// A ball.
    Sphere,
    /// A cylinder with round ends, along z.
    Capsule,
    /// A cylinder along z.
    Cylinder,
    /// An ellipsoid.
    Ellipsoid,
    /// A box.
    Box,
}

/// *(ext)* A sensor: one named reading, MuJoCo's sensor of the same type, in SI units
/// (m, rad, m/s, rad/s, N, N·m) in every unit system. Exactly the object its type reads is
/// set: `joint` (jointpos, jointvel), `actuator` (actuatorfrc: an actuator, or a joint
/// actuated directly), `tendon` (tendonpos, tendonvel), `site` or `instance` (the frame
/// sensors, whose `reference` may name another frame), `instance` (the subtree sensors:
/// the instance and everything jointed below it), or `site` (gyro, accelerometer,
/// velocimeter, magnetometer, touch, force, torque, rangefinder).
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SensorDef {
    /// Its name, unique among the sensors.
    pub name: String,
    /// What it reads (MuJoCo's element name: `jointpos`, `framequat`, `touch`, ...).
    #[serde(rename = "type")]
    pub kind: SensorType,
    /// The joint a joint sensor reads.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub joint: Option<String>,
    /// The actuator (or directly actuated joint) an `actuatorfrc` reads.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub actuator: Option<String>,
    /// The fixed tendon a tendon sensor reads.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tendon: Option<String>,
    /// The site a site sensor sits on, or whose frame a frame sensor reads.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub site: Option<String>,
    /// The instance whose frame a frame sensor reads, or whose subtree a subtree sensor.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub instance: Option<String>,
    /// A frame sensor's reference frame: its value is expressed in it (MuJoCo's
    /// `reftype`/`refname`); default the world.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reference: Option<SensorFrameDef>,
    /// When positive, the largest magnitude reported (MuJoCo's `cutoff`): a real value is
    /// clamped to `[-cutoff, cutoff]`, a non-negative one (touch, rangefinder) to
    /// `cutoff`; quaternions and axes are never cut.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cutoff: Option<f64>,
    /// The noise's standard deviation: metadata only, as in MuJoCo ≥ 3.1.4 (nothing is
    /// added to the reading).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub noise: Option<f64>,
}

/// A frame a frame sensor is expressed in: a site's, or an instance's.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SensorFrameDef {
    /// A site's frame.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub site: Option<String>,
    /// An instance's frame (its placement's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub instance: Option<String>,
}

/// What a sensor reads: MuJoCo's sensor types, by their MJCF element names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum SensorType {
    /// A hinge's (rad) or slide's (m) position, as observed.
    Jointpos,
    /// Its velocity.
    Jointvel,
    /// An actuator's force at its transmission, before the gear (MuJoCo's
    /// `actuator_force`).
    Actuatorfrc,
    /// A fixed tendon's length.
    Tendonpos,
    /// Its rate.
    Tendonvel,
    /// A frame's position.
    Framepos,
    /// A frame's orientation `[qw, qx, qy, qz]`.
    Framequat,
    /// A frame's x axis.
    Framexaxis,
    /// A frame's y axis.
    Frameyaxis,
    /// A frame's z axis.
    Framezaxis,
    /// A frame's linear velocity.
    Framelinvel,
    /// A frame's angular velocity.
    Frameangvel,
    /// A frame's linear acceleration (gravity not included).
    Framelinacc,
    /// A frame's angular acceleration.
    Frameangacc,
    /// The centre of mass of an instance and everything below it, world.
    Subtreecom,
    /// That subtree's centre-of-mass velocity, world.
    Subtreelinvel,
    /// That subtree's angular momentum about its centre of mass, world.
    Subtreeangmom,
    /// A site's angular velocity, in its own axes.
    Gyro,
    /// A site's linear acceleration minus gravity, in its own axes.
    Accelerometer,
    /// A site's linear velocity, in its own axes.
    Velocimeter,
    /// The magnetic field (`simulation.magnetic`, default MuJoCo's) in a site's axes.
    Magnetometer,
    /// The normal force of the contacts on a site's instance (and what is welded to it).
    Touch,
    /// The force a site's instance and its subtree receive from their parent, in the
    /// site's axes.
    Force,
    /// The torque they receive, about the site, in its axes.
    Torque,
    /// The distance along a site's +z axis to the nearest surface, −1 when none.
    Rangefinder,
}

impl SensorType {
    /// Floats the sensor reports (MuJoCo's `sensor_dim`).
    pub fn dim(self) -> usize {
        use SensorType::*;
        match self {
            Jointpos | Jointvel | Actuatorfrc | Tendonpos | Tendonvel | Touch | Rangefinder => 1,
            Framequat => 4,
            _ => 3,
        }
    }

    /// Its MJCF element name.
    pub fn as_str(self) -> &'static str {
        use SensorType::*;
        match self {
            Jointpos => "jointpos",
            Jointvel => "jointvel",
            Actuatorfrc => "actuatorfrc",
            Tendonpos => "tendonpos",
            Tendonvel => "tendonvel",
            Framepos => "framepos",
            Framequat => "framequat",
            Framexaxis => "framexaxis",
            Frameyaxis => "frameyaxis",
            Framezaxis => "framezaxis",
            Framelinvel => "framelinvel",
            Frameangvel => "frameangvel",
            Framelinacc => "framelinacc",
            Frameangacc => "frameangacc",
            Subtreecom => "subtreecom",
            Subtreelinvel => "subtreelinvel",
            Subtreeangmom => "subtreeangmom",
            Gyro => "gyro",
            Accelerometer => "accelerometer",
            Velocimeter => "velocimeter",
            Magnetometer => "magnetometer",
            Touch => "touch",
            Force => "force",
            Torque => "torque",
            Rangefinder => "rangefinder",
        }
    }

    /// Whether its value needs the accelerations of the last step.
    pub fn needs_acceleration(self) -> bool {
        use SensorType::*;
        matches!(
            self,
            Framelinacc | Frameangacc | Accelerometer | Force | Torque
        )
    }

    /// What its cutoff does: `Some(true)` clamps both ways, `Some(false)` only above
    /// (non-negative readings), `None` never (quaternions, axes).
    pub fn cutoff_kind(self) -> Option<bool> {
        use SensorType::*;
        match self {
            Framequat | Framexaxis | Frameyaxis | Framezaxis => None,
            Touch | Rangefinder => Some(false),
            _ => Some(true),
        }
    }
}
