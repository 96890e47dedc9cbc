//! *(ext)* Tendons (fixed: a combination of joint positions; spatial: a path through
//! sites) and couplings (a joint's or tendon's displacement held at a linear function of
//! another's), as MJCF's `<tendon>` and `<equality><joint|tendon>` define them.

use serde::{Deserialize, Serialize};

/// *(ext)* A tendon. A fixed tendon names `joints`: its length is Σ coef · position over
/// them, in SI (rad or m, each joint's position as observed, its `reference` included), as
/// MuJoCo defines it. A spatial tendon names `sites` instead: its length is the path's,
/// m, straight from each site to the next (MuJoCo's `<spatial>` through sites, without
/// wrapping geoms), and its force pulls each site toward its neighbours.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct TendonDef {
    /// The tendon's name (unique among tendons).
    pub name: String,
    /// A fixed tendon's joints (revolute or prismatic) and their coefficients.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub joints: Vec<TendonJointDef>,
    /// A spatial tendon's path: two or more sites of different instances' chains, in
    /// order.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub sites: Vec<String>,
    /// A spring on the length: force −stiffness · (length − spring_length), N or N·m per
    /// unit length, on each joint times its coefficient; default 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stiffness: Option<f64>,
    /// A damper on the length's rate, per unit rate; default 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping: Option<f64>,
    /// The spring's rest length; default the length at the document's pose.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spring_length: Option<f64>,
    /// Hard limits on the length, `[min, max]` (m or rad); default none. A spatial
    /// tendon's limit is a rope: only its `max` may hold, and `min` must be 0 or less.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub range: Option<[f64; 2]>,
}

/// One joint of a fixed tendon.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct TendonJointDef {
    /// The joint's name.
    pub joint: String,
    /// Its coefficient in the length.
    pub coef: f64,
}

/// *(ext)* A coupling: `joint1`'s displacement from the document's pose is held at
/// `polycoef[0] + polycoef[1] · ` `joint2`'s (MuJoCo's `<equality><joint>` with a linear
/// `polycoef`), or the same between two fixed tendons' lengths, each less its length at the
/// pose (`<equality><tendon>`). Without a second joint or tendon, the first is held at
/// `polycoef[0]` from the pose. Hard: the joints never leave it.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CouplingDef {
    /// The coupling's name (unique among couplings).
    pub name: String,
    /// The joint held (revolute or prismatic); or name `tendon1`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub joint1: Option<String>,
    /// The joint it follows; default none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub joint2: Option<String>,
    /// The fixed tendon held; or name `joint1`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tendon1: Option<String>,
    /// The fixed tendon it follows; default none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tendon2: Option<String>,
    /// `[offset, ratio]` in SI (rad or m; the ratio is unitless, or m/rad between a slide
    /// and a hinge); default `[0, 1]`. The ratio is unused without a second joint or tendon.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub polycoef: Option<Vec<f64>>,
}
