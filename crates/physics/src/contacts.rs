//! Contact forces read back from the solver: the external wrench the contacts of the last
//! step applied to each instance (MuJoCo's `cfrc_ext`).

use rapier3d::geometry::{PairContacts, NEW_CONTACT_BIT};
use rapier3d::math::{Real, Vector};
use rapier3d::utils::OrthonormalBasis;

use crate::world::RobotWorld;

/// Floats in a wrench: a torque (N·m), then a force (N), MuJoCo's `cfrc_ext` order.
pub const WRENCH_LEN: usize = 6;

impl RobotWorld {
    /// Writes into `out` (resized to one entry per instance, in document order) the wrench
    /// the last step's contacts applied to each instance: the torque about `about` (world
    /// metres) in N·m, then the force in N, both world axes, averaged over the step (over its
    /// last substep in a world stepped one pipeline step per substep, such as one with
    /// MuJoCo's compliant contacts: `RobotWorld::step`). This is MuJoCo's `cfrc_ext` of a
    /// body when `about` is its root's subtree centre of mass.
    ///
    /// Normal forces come from every contact; friction from the solver's per-point friction
    /// of contacts that involve a jointed instance (Rapier's multibody contacts are solved
    /// point by point); a contact between two unjointed bodies (Rapier's simplified friction
    /// model) reports its last substep's friction. Zeros after a reset.
    pub fn contact_wrenches(&self, about: [f64; 3], out: &mut Vec<[f64; WRENCH_LEN]>) {
        out.clear();
        out.resize(self.bodies.len(), [0.0; WRENCH_LEN]);
        self.for_each_contact(|a, b, at, _, force| {
            let arm = [at[0] - about[0], at[1] - about[1], at[2] - about[2]];
            for (instance, sign) in [(a, 1.0), (b, -1.0)] {
                let Some(k) = instance else { continue };
                let f = force.map(|v| sign * v);
                let w = &mut out[k];
                w[0] += arm[1] * f[2] - arm[2] * f[1];
                w[1] += arm[2] * f[0] - arm[0] * f[2];
                w[2] += arm[0] * f[1] - arm[1] * f[0];
                w[3] += f[0];
                w[4] += f[1];
                w[5] += f[2];
            }
        });
    }

    /// Calls `f(a, b, at, normal, force)` for every contact point of the last step: the two
    /// instances (`None` for a collider no instance owns), the point (world m), the normal
    /// force's magnitude (N) and the whole force on `a` (N, world; `b` gets its opposite),
    /// averaged over the step or its last substep (see [`RobotWorld::contact_wrenches`]).
    pub(crate) fn for_each_contact(
        &self,
        mut f: impl FnMut(Option<usize>, Option<usize>, [f64; 3], f64, [f64; 3]),
    ) {
        // A world stepped one pipeline step per substep keeps the last substep's impulses:
        // its forces are the last substep's (as MuJoCo's are its last timestep's).
        let (inv_dt, substeps) = if self.steps_by_substep() {
            (1.0 / f64::from(self.substep_params.dt), 1.0)
        } else {
            (1.0 / self.dt(), self.substeps as Real)
        };
        let s = &self.live;
        let instance_of = |collider| self.colliders.iter().position(|&c| c == collider);
        let multibody = |collider| {
            s.colliders
                .get(collider)
                .and_then(|c| c.parent())
                .is_some_and(|b| s.multibody_joints.rigid_body_link(b).is_some())
        };
        for pair in s.narrow_phase.contact_pairs() {
            let PairContacts::Rigid(rigid) = &pair.contacts else {
                continue;
            };
            let (a, b) = (instance_of(pair.collider1), instance_of(pair.collider2));
            if a.is_none() && b.is_none() {
                continue;
            }
            let (Some(c1), Some(c2)) = (
                s.colliders.get(pair.collider1),
                s.colliders.get(pair.collider2),
            ) else {
                continue;
            };
            // Per point friction totals only where the solver keeps them (see above).
            let per_point = multibody(pair.collider1) || multibody(pair.collider2);
            // The solver works on the clusters when contact clustering made some.
            let manifolds = if rigid.solver_clusters.is_empty() {
                &rigid.manifolds
            } else {
                &rigid.solver_clusters
            };
            for manifold in manifolds {
                // The impulses push body 1 along the solver's direction, −normal.
                let dir: Vector = -manifold.data.normal;
                let t1 = dir.orthonormal_vector();
                let t2 = dir.cross(t1);
                for contact in &manifold.data.solver_contacts {
                    let id = (contact.contact_id[0] & !NEW_CONTACT_BIT) as usize;
                    let Some(point) = manifold.points.get(id) else {
                        continue;
                    };
                    let d = &point.data;
                    let friction: Vector = if per_point {
                        t1 * d.tangent_impulse.x + t2 * d.tangent_impulse.y
                    } else {
                        d.warmstart_tangent_world * substeps
                    };
                    let impulse = dir * d.impulse + friction;
                    let p1 = c1.position().transform_point(point.local_p1);
                    let p2 = c2.position().transform_point(point.local_p2);
                    let at = (p1 + p2) * 0.5;
                    let force = [impulse.x, impulse.y, impulse.z].map(|v| f64::from(v) * inv_dt);
                    let normal = f64::from(d.impulse) * inv_dt;
                    f(a, b, [at.x, at.y, at.z].map(f64::from), normal, force);
                }
            }
        }
    }
}
