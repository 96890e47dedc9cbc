//! Where a multibody's per-substep buffers lie (gymfleet patch 37, see `PATCHES.md`).

use super::Multibody;
use crate::pipeline::slice_span;

impl Multibody {
    /// Calls `f` with the address and size in bytes of each buffer the dynamics fill and read
    /// at every substep (the mass matrices and their factors, the accelerations, the
    /// workspaces of the accelerations and of the composite construction), as the last step
    /// left them. The links and body jacobians are public already ([`Multibody::links`],
    /// [`Multibody::body_jacobian`]).
    ///
    /// For a caller that steps many worlds one after another and prefetches the next world's
    /// memory (see [`crate::pipeline::PhysicsPipeline::workspace_buffers`]). Nothing is read
    /// through the addresses, and a buffer may move at the next step.
    pub fn workspace_buffers(&self, mut f: impl FnMut(usize, usize)) {
        let mut visit = |(address, bytes): (usize, usize)| {
            if bytes > 0 {
                f(address, bytes);
            }
        };
        visit(slice_span(self.augmented_mass.as_slice()));
        visit(slice_span(self.acc_augmented_mass.as_slice()));
        visit(slice_span(self.inv_augmented_mass.storage()));
        visit(slice_span(self.acc_inv_augmented_mass.storage()));
        visit(slice_span(self.accelerations.as_slice()));
        visit(slice_span(self.velocities.as_slice()));
        visit(slice_span(self.damping.as_slice()));
        visit(slice_span(self.armature.as_slice()));
        visit(slice_span(self.applied_forces.as_slice()));
        let ws = &self.workspace;
        visit(slice_span(&ws.accs));
        visit(slice_span(&ws.link_inertias));
        visit(slice_span(ws.pos_forces.as_slice()));
        visit(slice_span(ws.gen_forces.as_slice()));
        #[cfg(feature = "dim3")]
        {
            visit(slice_span(&ws.wrenches));
            for row in &ws.jacobian_rows {
                visit(slice_span(row));
            }
            self.composite_workspace.buffers(&mut visit);
        }
    }
}
