//! The document's `simulation` *(ext)*: the world's gravity, the env step the description
//! was made for, the still fluid the bodies move in, and how the joint trees' velocity terms
//! enter a substep.

use crate::document::{FluidDef, Integrator, SimulationDef};
use crate::error::Issue;
use crate::model::{Fluid, DEFAULT_GRAVITY};

/// Largest gravity component, m/s² (about 100 g).
const MAX_GRAVITY: f64 = 1000.0;
/// Longest env step a document may ask for, s (an env's own bound may be tighter).
const MAX_DT: f64 = 1.0;
/// Densest fluid a document may ask for, kg/m³ (seven times mercury).
pub const MAX_FLUID_DENSITY: f64 = 1e5;
/// Most viscous fluid a document may ask for, Pa·s (about a million times water; pitch is
/// far above, honey is about 10).
pub const MAX_FLUID_VISCOSITY: f64 = 1e3;

/// The validated `simulation`: gravity (m/s²), the env step it asks for (s) and the fluid.
pub(crate) struct Simulation {
    pub(crate) gravity: [f64; 3],
    pub(crate) dt: Option<f64>,
    pub(crate) fluid: Option<Fluid>,
    pub(crate) integrator: Integrator,
    pub(crate) magnetic: [f64; 3],
}

/// MuJoCo's default magnetic field, T.
pub const DEFAULT_MAGNETIC: [f64; 3] = [0.0, -0.5, 0.0];
/// Largest magnetic field component, T.
const MAX_MAGNETIC: f64 = 1e3;

/// The document's `simulation`, checked; every problem is an issue.
pub(crate) fn simulation(def: Option<&SimulationDef>) -> (Simulation, Vec<Issue>) {
    let mut issues = Vec::new();
    let Some(def) = def else {
        let defaults = Simulation {
            gravity: DEFAULT_GRAVITY,
            dt: None,
            fluid: None,
            integrator: Integrator::Implicit,
            magnetic: DEFAULT_MAGNETIC,
        };
        return (defaults, issues);
    };
    let gravity = match def.gravity {
        Some(g) => {
            for (axis, c) in [("x", g.x), ("y", g.y), ("z", g.z)] {
                if !(c.is_finite() && c.abs() <= MAX_GRAVITY) {
                    issues.push(Issue::new(
                        format!("simulation.gravity.{axis}"),
                        format!("expected a component within ±{MAX_GRAVITY} m/s², got {c}"),
                    ));
                }
            }
            g.to_array()
        }
        None => DEFAULT_GRAVITY,
    };
    if let Some(dt) = def.dt {
        if !(dt.is_finite() && dt > 0.0 && dt <= MAX_DT) {
            issues.push(Issue::new(
                "simulation.dt",
                format!("expected an env step in (0, {MAX_DT}] s, got {dt}"),
            ));
        }
    }
    let fluid = def.fluid.as_ref().and_then(|f| fluid(f, &mut issues));
    let magnetic = def.magnetic.map_or(DEFAULT_MAGNETIC, |m| m.to_array());
    for (axis, c) in ["x", "y", "z"].iter().zip(magnetic) {
        if !(c.is_finite() && c.abs() <= MAX_MAGNETIC) {
            issues.push(Issue::new(
                format!("simulation.magnetic.{axis}"),
                format!("expected a component within ±{MAX_MAGNETIC} T, got {c}"),
            ));
        }
    }
    let simulation = Simulation {
        magnetic,
        gravity,
        dt: def.dt,
        fluid,
        integrator: def.integrator.unwrap_or_default(),
    };
    (simulation, issues)
}

/// `simulation.fluid`: `None` when both coefficients are 0 (no drag at all).
fn fluid(def: &FluidDef, issues: &mut Vec<Issue>) -> Option<Fluid> {
    let mut coefficient = |name: &str, value: Option<f64>, max: f64, unit: &str| {
        let value = value.unwrap_or(0.0);
        if !(value.is_finite() && (0.0..=max).contains(&value)) {
            issues.push(Issue::new(
                format!("simulation.fluid.{name}"),
                format!("expected a {name} in [0, {max}] {unit}, got {value}"),
            ));
        }
        value
    };
    let density = coefficient("density", def.density, MAX_FLUID_DENSITY, "kg/m³");
    let viscosity = coefficient("viscosity", def.viscosity, MAX_FLUID_VISCOSITY, "Pa·s");
    (density > 0.0 || viscosity > 0.0).then_some(Fluid { density, viscosity })
}
