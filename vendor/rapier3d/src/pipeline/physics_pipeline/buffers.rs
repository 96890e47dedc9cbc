//! Where the solver's per-step buffers lie (gymfleet patch 37, see `PATCHES.md`).

use super::PhysicsPipeline;

/// `(address, bytes)` of a slice's elements.
pub(crate) fn slice_span<T>(values: &[T]) -> (usize, usize) {
    (values.as_ptr().addr(), core::mem::size_of_val(values))
}

impl PhysicsPipeline {
    /// Calls `f` with the address and size in bytes of each buffer the constraint solver
    /// fills and reads at every step (the contact and joint constraints, their builders and
    /// jacobians, the solver bodies and velocities), as the last step left them.
    ///
    /// For a caller that steps many worlds one after another and hints the processor to
    /// prefetch the next world's memory while the current one steps: with a few hundred
    /// worlds per core their buffers no longer stay in the caches from one step to the next.
    /// Nothing is read through the addresses, and a buffer may move at the next step.
    pub fn workspace_buffers(&self, mut f: impl FnMut(usize, usize)) {
        let solver = &self.staged_solver;
        let contacts = &solver.contact_constraints;
        let joints = &solver.joint_constraints;
        let velocities = &solver.velocity_solver;
        for (address, bytes) in [
            slice_span(contacts.generic_jacobians.as_slice()),
            slice_span(&contacts.generic_velocity_constraints),
            slice_span(&contacts.generic_velocity_constraints_builder),
            slice_span(&contacts.simd_velocity_coulomb_constraints),
            slice_span(&contacts.simd_velocity_coulomb_constraints_builder),
            slice_span(&contacts.simd_velocity_twist_constraints),
            slice_span(&contacts.simd_velocity_twist_constraints_builder),
            slice_span(joints.generic_jacobians.as_slice()),
            slice_span(&joints.generic_velocity_constraints),
            slice_span(&joints.generic_velocity_constraints_builder),
            slice_span(&joints.velocity_constraints),
            slice_span(&joints.velocity_constraints_builder),
            slice_span(&joints.simd_velocity_constraints),
            slice_span(&joints.simd_velocity_constraints_builder),
            slice_span(&velocities.solver_bodies.vels),
            slice_span(&velocities.solver_bodies.poses),
            slice_span(&velocities.solver_bodies.flags),
            slice_span(&velocities.solver_vels_increment),
            slice_span(velocities.generic_solver_vels.as_slice()),
            slice_span(velocities.generic_solver_vels_increment.as_slice()),
            slice_span(&velocities.multibody_roots),
        ] {
            if bytes > 0 {
                f(address, bytes);
            }
        }
    }
}
