//! A document's contact rules *(ext)*: pairs of instances that never collide, and pairs that
//! always do (MJCF's `<contact>`).

use serde::{Deserialize, Serialize};

/// *(ext)* Contact rules: pairs of instances that never collide, and pairs that always do.
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ContactsDef {
    /// Pairs of instances kept from colliding (MJCF's `<exclude>`, one pair per two of its
    /// bodies' instances).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub exclude: Vec<ContactExcludeDef>,
    /// Pairs of instances that collide whatever their collision bits and exclusions say,
    /// with their own friction (MJCF's `<pair>`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub pairs: Vec<ContactPairDef>,
}

/// *(ext)* Two instances kept from colliding.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ContactExcludeDef {
    /// One instance.
    pub a: String,
    /// The other.
    pub b: String,
}

/// *(ext)* Two instances that always collide.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ContactPairDef {
    /// One instance.
    pub a: String,
    /// The other.
    pub b: String,
    /// The pair's sliding friction coefficient; default the instances' own, combined.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction: Option<f64>,
    /// 1: frictionless; 3 (the default): sliding friction.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub condim: Option<u32>,
}
