//! A still fluid around the bodies: MuJoCo's inertia-box model (`engine_passive.c`,
//! `mj_inertiaBoxFluidModel`), which `<option density viscosity>` turns on.
//!
//! Each rigid body (instances welded by fixed joints count as one, as they are one MuJoCo
//! body) is replaced, for the fluid, by the box with its mass and principal moments of
//! inertia, moving with the body's velocity at its centre of mass. In the box's axes:
//! - viscosity μ gives Stokes' drag of the sphere whose diameter d is the box's mean edge:
//!   force −3π·d·μ·v, torque −π·d³·μ·ω;
//! - density ρ gives quadratic drag on each face: force −½·ρ·(face area)·|v|·v along each
//!   axis, torque −ρ·bᵢ·(bⱼ⁴ + bₖ⁴)/64·|ωᵢ|·ωᵢ about each.
//!
//! The forces depend on the state, so they are recomputed before every substep (as
//! MuJoCo recomputes its passive forces every step). MuJoCo's wind and its ellipsoid model
//! (`fluidshape`) are not modelled; the MJCF import refuses them.

use std::f32::consts::PI;

use gymfleet_assembly::Assembly;
use rapier3d::prelude::*;

use crate::world::{FluidDrag, RobotWorld, Sets};

/// MuJoCo's `mjMINVAL`: the floor of a box's squared edge before the square root.
const MIN_VALUE: Real = 1e-15;

impl FluidDrag {
    /// The assembly's fluid over its moving rigid groups; `None` without a fluid.
    pub(crate) fn new(
        assembly: &Assembly,
        bodies: &[RigidBodyHandle],
        sets: &Sets,
    ) -> Option<Self> {
        let fluid = assembly.fluid?;
        let group = crate::contact_filter::rigid_groups(assembly);
        let mut groups: Vec<Vec<RigidBodyHandle>> = Vec::new();
        let mut index = vec![usize::MAX; bodies.len()];
        for (k, &body) in bodies.iter().enumerate() {
            let g = group[k];
            if index[g] == usize::MAX {
                index[g] = groups.len();
                groups.push(Vec::new());
            }
            // Folded instances share their owner's body: each body once.
            if !groups[index[g]].contains(&body) {
                groups[index[g]].push(body);
            }
        }
        // A group welded to the ground does not move through the fluid.
        groups.retain(|g| g.iter().all(|&h| sets.bodies[h].is_dynamic()));
        Some(FluidDrag {
            density: fluid.density as Real,
            viscosity: fluid.viscosity as Real,
            groups,
        })
    }
}

impl RobotWorld {
    /// Adds each moving group's drag to the user force and torque of its first body, from
    /// the current state (see the module documentation). Without a fluid it does nothing.
    pub(crate) fn apply_fluid(&mut self) {
        let Some(fluid) = &self.fluid else { return };
        let bodies = &mut self.live.bodies;
        for group in &fluid.groups {
            let Some((force, torque)) = fluid.drag(bodies, group) else {
                continue;
            };
            // Cleared before the substep's efforts (`clear_body_forces`).
            let first = &mut bodies[group[0]];
            first.add_force(force, true);
            first.add_torque(torque, true);
        }
    }
}

impl FluidDrag {
    /// The drag on one group: the force (N) and the torque (N·m) about its first body's
    /// centre of mass, world axes. `None` for a massless group.
    fn drag(&self, bodies: &RigidBodySet, group: &[RigidBodyHandle]) -> Option<(Vector, Vector)> {
        let first = &bodies[group[0]];
        let pose = *first.position();
        // The group's mass properties in its first body's frame.
        let mut props = first.mass_properties().local_mprops;
        for &h in &group[1..] {
            let relative = pose.inverse() * *bodies[h].position();
            props += bodies[h]
                .mass_properties()
                .local_mprops
                .transform_by(&relative);
        }
        let mass = props.mass();
        if !(mass > 0.0 && mass.is_finite()) {
            return None;
        }
        let i = props.principal_inertia();
        let edge = |a: Real, b: Real, c: Real| ((b + c - a).max(MIN_VALUE) / mass * 6.0).sqrt();
        let size = Vector::new(
            edge(i.x, i.y, i.z),
            edge(i.y, i.x, i.z),
            edge(i.z, i.x, i.y),
        );
        let axes = pose.rotation * props.principal_inertia_local_frame;
        let com = pose.transform_point(props.local_com);
        let angvel = first.angvel();
        let linvel = first.linvel() + angvel.cross(com - first.mass_properties().world_com);
        // In the box's axes.
        let w = axes.inverse() * angvel;
        let v = axes.inverse() * linvel;
        let mut torque = Vector::ZERO;
        let mut force = Vector::ZERO;
        if self.viscosity > 0.0 {
            let d = (size.x + size.y + size.z) / 3.0;
            torque -= w * (PI * d * d * d * self.viscosity);
            force -= v * (3.0 * PI * d * self.viscosity);
        }
        if self.density > 0.0 {
            let rho = self.density;
            let s = size;
            let area = Vector::new(s.y * s.z, s.x * s.z, s.x * s.y);
            force -= 0.5 * rho * area * v.abs() * v;
            let s4 = s * s * s * s;
            let arm = Vector::new(
                s.x * (s4.y + s4.z),
                s.y * (s4.x + s4.z),
                s.z * (s4.x + s4.y),
            );
            torque -= rho / 64.0 * arm * w.abs() * w;
        }
        let force = axes * force;
        let torque = axes * torque + (com - first.mass_properties().world_com).cross(force);
        Some((force, torque))
    }
}
