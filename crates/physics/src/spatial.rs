//! Spatial tendons through sites (MuJoCo's `<tendon><spatial>` without wrapping geoms): the
//! length is the straight path's, Σ |pᵢ₊₁ − pᵢ| over the sites' world points, and its rate
//! `J·q̇`, `J` the length's jacobian over the trees' generalized velocities (each segment's
//! direction at its two ends, through the links' body jacobians). A force `f` along the
//! tendon (a spring, a damper, an actuator; positive lengthens) acts as the generalized
//! force `Jᵀ·f`: each site is pulled toward its neighbours by `−f`. A site on a free body
//! outside the trees (an object) moves with that body's own velocity and takes the force as
//! a user force at its point, cleared before every substep. A ranged tendon is a rope: its
//! `max` is a hard limit, enforced after every substep with the joints' hard stops (vendored
//! patch 42; MuJoCo's limit is soft); its sites must move with one tree or not at all.

use std::collections::HashMap;

use gymfleet_assembly::{Assembly, Tendon};
use rapier3d::dynamics::MultibodyPathLimit;
use rapier3d::prelude::*;

use crate::error::{PhysicsError, Result};
use crate::units::to_m;
use crate::world::{PathPoint, RobotWorld, Sets};

/// The path of spatial tendon `tendon` (empty for a fixed one): each site's body and its
/// point in that body's frame (`placements`: each instance's frame in its body's).
pub(crate) fn path_points(
    assembly: &Assembly,
    tendon: &Tendon,
    bodies: &[RigidBodyHandle],
    placements: &[Pose],
) -> Vec<PathPoint> {
    tendon
        .sites
        .iter()
        .map(|&s| {
            let site = &assembly.sites[s];
            let [x, y, z] = site.point.map(|v| to_m(v) as Real);
            PathPoint {
                body: bodies[site.instance],
                local: placements[site.instance] * Vector::new(x, y, z),
            }
        })
        .collect()
}

/// The path's length with the bodies where `sets` holds them, m.
pub(crate) fn path_length(path: &[PathPoint], sets: &Sets) -> f64 {
    let world: Vec<Vector> = path
        .iter()
        .map(|p| *sets.bodies[p.body].position() * p.local)
        .collect();
    world
        .windows(2)
        .map(|w| f64::from((w[1] - w[0]).length()))
        .sum()
}

/// Puts each ranged spatial tendon's rope on the multibody its moving sites share
/// (vendored patch 42). A site on a body that does not move is a fixed world point.
pub(crate) fn set_path_limits(
    assembly: &Assembly,
    paths: &[Vec<PathPoint>],
    sets: &mut Sets,
) -> Result<()> {
    let mut by_multibody: HashMap<MultibodyIndex, Vec<MultibodyPathLimit>> = HashMap::new();
    for (t, path) in assembly.tendons.iter().zip(paths) {
        let Some([_, max]) = t.range.filter(|_| t.is_spatial()) else {
            continue;
        };
        let mut tree = None;
        let mut points = Vec::with_capacity(path.len());
        for p in path {
            let body = &sets.bodies[p.body];
            // A point of a body that never moves (a static tree root too) is a fixed world
            // point.
            if !body.is_dynamic() {
                points.push((None, *body.position() * p.local));
                continue;
            }
            match sets.multibody_joints.rigid_body_link(p.body) {
                Some(link) if tree.is_none_or(|m| m == link.multibody) => {
                    tree = Some(link.multibody);
                    points.push((Some(link.id), p.local));
                }
                _ => {
                    return Err(PhysicsError::BadOption {
                        field: "assembly.tendons",
                        reason: format!(
                            "tendon {:?} has a range, and its sites move with different kinematic trees or with a free body; a ranged spatial tendon's moving sites must share one tree",
                            t.name
                        ),
                    })
                }
            }
        }
        // A rope whose every point is fixed holds nothing.
        if let Some(tree) = tree {
            by_multibody
                .entry(tree)
                .or_default()
                .push(MultibodyPathLimit {
                    points,
                    max: max as Real,
                });
        }
    }
    for (multibody, limits) in by_multibody {
        if let Some(mb) = sets.multibody_joints.get_multibody_mut(multibody) {
            mb.set_path_limits(limits);
        }
    }
    Ok(())
}

/// A path's length jacobian: for each tree it moves, its row over that tree's generalized
/// velocities; and for each end of a segment on a free body outside the trees, the body,
/// the world point and the direction that lengthens the path.
#[derive(Default)]
struct PathJacobian {
    trees: Vec<(MultibodyIndex, DVector)>,
    free: Vec<(RigidBodyHandle, Vector, Vector)>,
}

impl RobotWorld {
    /// The path's sites in the world, m.
    fn path_world(&self, path: &[PathPoint]) -> Vec<Vector> {
        path.iter()
            .map(|p| *self.live.bodies[p.body].position() * p.local)
            .collect()
    }

    /// The path's length jacobian (see [`PathJacobian`]).
    fn path_jacobian(&self, path: &[PathPoint], world: &[Vector]) -> PathJacobian {
        let mut rows = PathJacobian::default();
        for (i, w) in world.windows(2).enumerate() {
            let along = w[1] - w[0];
            let len = along.length();
            if len <= Real::EPSILON {
                continue;
            }
            let dir = along / len;
            for (point, at, sign) in [(&path[i + 1], w[1], 1.0), (&path[i], w[0], -1.0)] {
                self.add_point_row(&mut rows, point.body, at, dir * sign);
            }
        }
        rows
    }

    /// Adds `dir · v` of world point `at` on `body` to the jacobian (a free body's as its
    /// own; nothing for a body that does not move).
    fn add_point_row(
        &self,
        rows: &mut PathJacobian,
        body: RigidBodyHandle,
        at: Vector,
        dir: Vector,
    ) {
        let Some(link) = self.live.multibody_joints.rigid_body_link(body) else {
            if self.live.bodies[body].is_dynamic() {
                rows.free.push((body, at, dir));
            }
            return;
        };
        let Some(mb) = self.live.multibody_joints.get_multibody(link.multibody) else {
            return;
        };
        let rb = &self.live.bodies[body];
        let com = *rb.position() * rb.mass_properties().local_mprops.local_com;
        let arm = (at - com).cross(dir);
        let trees = &mut rows.trees;
        let k = match trees.iter().position(|(m, _)| *m == link.multibody) {
            Some(k) => k,
            None => {
                trees.push((link.multibody, DVector::zeros(mb.ndofs())));
                trees.len() - 1
            }
        };
        let columns = mb.body_jacobian(link.id).as_slice().chunks_exact(6);
        for (entry, c) in trees[k].1.iter_mut().zip(columns) {
            *entry += dir.x * c[0]
                + dir.y * c[1]
                + dir.z * c[2]
                + arm.x * c[3]
                + arm.y * c[4]
                + arm.z * c[5];
        }
    }

    /// A spatial tendon's length (m) and rate (m/s).
    pub(crate) fn path_state(&self, path: &[PathPoint]) -> (f64, f64) {
        let world = self.path_world(path);
        let length: f64 = world
            .windows(2)
            .map(|w| f64::from((w[1] - w[0]).length()))
            .sum();
        let jacobian = self.path_jacobian(path, &world);
        let trees: f64 = jacobian
            .trees
            .iter()
            .filter_map(|(m, row)| {
                let mb = self.live.multibody_joints.get_multibody(*m)?;
                Some(f64::from(row.dot(&mb.generalized_velocity())))
            })
            .sum();
        let free: f64 = jacobian
            .free
            .iter()
            .map(|&(body, at, dir)| {
                f64::from(dir.dot(self.live.bodies[body].velocity_at_point(at)))
            })
            .sum();
        (length, trees + free)
    }

    /// Adds the generalized forces of `force` along a spatial tendon (N; positive
    /// lengthens) to the trees it moves.
    pub(crate) fn add_path_force(&mut self, path: &[PathPoint], force: f64) {
        let world = self.path_world(path);
        let jacobian = self.path_jacobian(path, &world);
        for (m, row) in jacobian.trees {
            if let Some(mb) = self.live.multibody_joints.get_multibody_mut(m) {
                mb.applied_forces_mut().axpy(force as Real, &row, 1.0);
            }
        }
        for (body, at, dir) in jacobian.free {
            self.live.bodies[body].add_force_at_point(dir * force as Real, at, true);
        }
    }

    /// Clears the user forces of the free bodies that spatial tendons pull and of the
    /// fluid's groups, before a substep's efforts set them again (they would add up).
    pub(crate) fn clear_body_forces(&mut self) {
        let live = &mut self.live;
        let free = self
            .tendons
            .iter()
            .flat_map(|t| t.path.iter().map(|p| p.body))
            .filter(|&b| live.multibody_joints.rigid_body_link(b).is_none());
        let fluid = self
            .fluid
            .iter()
            .flat_map(|f| f.groups.iter().map(|g| g[0]));
        for body in free.chain(fluid) {
            if let Some(rb) = live.bodies.get_mut(body) {
                rb.reset_forces(false);
                rb.reset_torques(false);
            }
        }
    }

    /// A spatial tendon's moment arm on DOF `dof`: ∂length/∂q of that DOF (its column of
    /// the jacobian), 0 where the tendon does not move it.
    pub(crate) fn path_moment(&self, path: &[PathPoint], dof: usize) -> f64 {
        let slot = &self.joints[self.dofs[dof].joint];
        let Some(mb) = self.live.multibody_joints.get_multibody(slot.multibody) else {
            return 0.0;
        };
        let Some(first) = mb.link(slot.link).map(|link| link.assembly_id()) else {
            return 0.0;
        };
        let in_joint = dof - slot.first_dof;
        let world = self.path_world(path);
        self.path_jacobian(path, &world)
            .trees
            .iter()
            .find(|(m, _)| *m == slot.multibody)
            .map_or(0.0, |(_, row)| {
                f64::from(row[slot.link_dof(first, in_joint)])
            })
    }
}
