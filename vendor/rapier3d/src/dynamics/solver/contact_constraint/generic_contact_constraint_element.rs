use crate::dynamics::solver::SolverVel;
use crate::dynamics::solver::contact_constraint::GenericContactConstraint;
use crate::dynamics::solver::{ContactConstraintNormalPart, ContactConstraintTangentPart};
use crate::math::{AngVector, DIM, DVector, Real, Vector};
use crate::utils::{ComponentMul, DotProduct};
#[cfg(feature = "dim2")]
use {crate::utils::OrthonormalBasis, na::SimdPartialOrd};

pub(crate) enum GenericRhs {
    SolverVel(SolverVel<Real>),
    GenericId(u32),
    Fixed,
}

// Offset between the jacobians of two consecutive constraints.
#[inline]
pub(crate) fn j_step(ndofs1: usize, ndofs2: usize) -> usize {
    (ndofs1 + ndofs2) * 2
}

#[inline]
fn j_id1(j_id: usize, _ndofs1: usize, _ndofs2: usize) -> usize {
    j_id
}

#[inline]
fn j_id2(j_id: usize, ndofs1: usize, _ndofs2: usize) -> usize {
    j_id + ndofs1 * 2
}

#[inline]
fn normal_j_id(j_id: usize, _ndofs1: usize, _ndofs2: usize) -> usize {
    j_id
}

#[inline]
fn tangent_j_id(j_id: usize, ndofs1: usize, ndofs2: usize) -> usize {
    j_id + (ndofs1 + ndofs2) * 2
}

impl GenericRhs {
    #[inline]
    pub(crate) fn dvel(
        &self,
        j_id: usize,
        ndofs: usize,
        jacobians: &DVector,
        dir: Vector,
        gcross: AngVector,
        solver_vels: &DVector,
    ) -> Real {
        match self {
            GenericRhs::SolverVel(rhs) => dir.dot(rhs.linear) + gcross.gdot(rhs.angular),
            GenericRhs::GenericId(solver_vel) => {
                let j = jacobians.rows(j_id, ndofs);
                let rhs = solver_vels.rows(*solver_vel as usize, ndofs);
                j.dot(&rhs)
            }
            GenericRhs::Fixed => 0.0,
        }
    }

    #[inline]
    pub(crate) fn apply_impulse(
        &mut self,
        j_id: usize,
        ndofs: usize,
        impulse: Real,
        jacobians: &DVector,
        dir: Vector,
        ii_torque_dir: AngVector,
        solver_vels: &mut DVector,
        inv_mass: Vector,
    ) {
        match self {
            GenericRhs::SolverVel(rhs) => {
                rhs.linear += dir.component_mul(&inv_mass) * impulse;
                #[cfg(feature = "dim2")]
                {
                    // In 2D, angular values are scalars
                    rhs.angular += ii_torque_dir * impulse;
                }
                #[cfg(feature = "dim3")]
                {
                    rhs.angular += ii_torque_dir * impulse;
                }
            }
            GenericRhs::GenericId(solver_vel) => {
                let wj_id = j_id + ndofs;
                let wj = jacobians.rows(wj_id, ndofs);
                let mut rhs = solver_vels.rows_mut(*solver_vel as usize, ndofs);
                rhs.axpy(impulse, &wj, 1.0);
            }
            GenericRhs::Fixed => {}
        }
    }
}

impl ContactConstraintTangentPart<Real> {
    #[inline]
    pub fn generic_warmstart(
        &mut self,
        j_id: usize,
        jacobians: &DVector,
        tangents1: [Vector; DIM - 1],
        im1: Vector,
        im2: Vector,
        ndofs1: usize,
        ndofs2: usize,
        solver_vel1: &mut GenericRhs,
        solver_vel2: &mut GenericRhs,
        solver_vels: &mut DVector,
    ) {
        let j_id1 = j_id1(j_id, ndofs1, ndofs2);
        let j_id2 = j_id2(j_id, ndofs1, ndofs2);
        #[cfg(feature = "dim3")]
        let j_step = j_step(ndofs1, ndofs2);

        #[cfg(feature = "dim2")]
        {
            solver_vel1.apply_impulse(
                j_id1,
                ndofs1,
                self.impulse[0],
                jacobians,
                tangents1[0],
                self.ii_torque_dir1[0],
                solver_vels,
                im1,
            );
            solver_vel2.apply_impulse(
                j_id2,
                ndofs2,
                self.impulse[0],
                jacobians,
                -tangents1[0],
                self.ii_torque_dir2[0],
                solver_vels,
                im2,
            );
        }

        #[cfg(feature = "dim3")]
        {
            solver_vel1.apply_impulse(
                j_id1,
                ndofs1,
                self.impulse[0],
                jacobians,
                tangents1[0],
                self.ii_torque_dir1[0],
                solver_vels,
                im1,
            );
            solver_vel1.apply_impulse(
                j_id1 + j_step,
                ndofs1,
                self.impulse[1],
                jacobians,
                tangents1[1],
                self.ii_torque_dir1[1],
                solver_vels,
                im1,
            );

            solver_vel2.apply_impulse(
                j_id2,
                ndofs2,
                self.impulse[0],
                jacobians,
                -tangents1[0],
                self.ii_torque_dir2[0],
                solver_vels,
                im2,
            );
            solver_vel2.apply_impulse(
                j_id2 + j_step,
                ndofs2,
                self.impulse[1],
                jacobians,
                -tangents1[1],
                self.ii_torque_dir2[1],
                solver_vels,
                im2,
            );
        }
    }

    #[inline]
    pub fn generic_solve(
        &mut self,
        j_id: usize,
        jacobians: &DVector,
        tangents1: [Vector; DIM - 1],
        im1: Vector,
        im2: Vector,
        ndofs1: usize,
        ndofs2: usize,
        limit: Real,
        cfm: [Real; DIM - 1],
        pyramid: Option<[Real; 2]>,
        solver_vel1: &mut GenericRhs,
        solver_vel2: &mut GenericRhs,
        solver_vels: &mut DVector,
    ) {
        let j_id1 = j_id1(j_id, ndofs1, ndofs2);
        let j_id2 = j_id2(j_id, ndofs1, ndofs2);
        #[cfg(feature = "dim3")]
        let j_step = j_step(ndofs1, ndofs2);

        #[cfg(feature = "dim2")]
        {
            let dvel_0 = solver_vel1.dvel(
                j_id1,
                ndofs1,
                jacobians,
                tangents1[0],
                self.torque_dir1[0],
                solver_vels,
            ) + solver_vel2.dvel(
                j_id2,
                ndofs2,
                jacobians,
                -tangents1[0],
                self.torque_dir2[0],
                solver_vels,
            ) + self.rhs[0];

            let new_impulse =
                (cfm[0] * (self.impulse[0] - self.r[0] * dvel_0)).simd_clamp(-limit, limit);
            let dlambda = new_impulse - self.impulse[0];
            self.impulse[0] = new_impulse;

            solver_vel1.apply_impulse(
                j_id1,
                ndofs1,
                dlambda,
                jacobians,
                tangents1[0],
                self.ii_torque_dir1[0],
                solver_vels,
                im1,
            );
            solver_vel2.apply_impulse(
                j_id2,
                ndofs2,
                dlambda,
                jacobians,
                -tangents1[0],
                self.ii_torque_dir2[0],
                solver_vels,
                im2,
            );
        }

        #[cfg(feature = "dim3")]
        {
            let dvel_0 = solver_vel1.dvel(
                j_id1,
                ndofs1,
                jacobians,
                tangents1[0],
                self.torque_dir1[0],
                solver_vels,
            ) + solver_vel2.dvel(
                j_id2,
                ndofs2,
                jacobians,
                -tangents1[0],
                self.torque_dir2[0],
                solver_vels,
            ) + self.rhs[0];
            let dvel_1 = solver_vel1.dvel(
                j_id1 + j_step,
                ndofs1,
                jacobians,
                tangents1[1],
                self.torque_dir1[1],
                solver_vels,
            ) + solver_vel2.dvel(
                j_id2 + j_step,
                ndofs2,
                jacobians,
                -tangents1[1],
                self.torque_dir2[1],
                solver_vels,
            ) + self.rhs[1];

            // gymfleet patch 43: a compliant point's friction rows are regularised (`cfm`,
            // 1 for Rapier's rigid rows).
            let new_impulse = na::Vector2::new(
                cfm[0] * (self.impulse[0] - self.r[0] * dvel_0),
                cfm[1] * (self.impulse[1] - self.r[1] * dvel_1),
            );
            let new_impulse = match pyramid {
                Some(axes) => pyramid_section(new_impulse, axes, limit),
                None => new_impulse.cap_magnitude(limit),
            };

            let dlambda = new_impulse - self.impulse;
            self.impulse = new_impulse;

            solver_vel1.apply_impulse(
                j_id1,
                ndofs1,
                dlambda[0],
                jacobians,
                tangents1[0],
                self.ii_torque_dir1[0],
                solver_vels,
                im1,
            );
            solver_vel1.apply_impulse(
                j_id1 + j_step,
                ndofs1,
                dlambda[1],
                jacobians,
                tangents1[1],
                self.ii_torque_dir1[1],
                solver_vels,
                im1,
            );

            solver_vel2.apply_impulse(
                j_id2,
                ndofs2,
                dlambda[0],
                jacobians,
                -tangents1[0],
                self.ii_torque_dir2[0],
                solver_vels,
                im2,
            );
            solver_vel2.apply_impulse(
                j_id2 + j_step,
                ndofs2,
                dlambda[1],
                jacobians,
                -tangents1[1],
                self.ii_torque_dir2[1],
                solver_vels,
                im2,
            );
        }
    }
}

impl ContactConstraintNormalPart<Real> {
    #[inline]
    pub fn generic_warmstart(
        &mut self,
        j_id: usize,
        jacobians: &DVector,
        dir1: Vector,
        im1: Vector,
        im2: Vector,
        ndofs1: usize,
        ndofs2: usize,
        solver_vel1: &mut GenericRhs,
        solver_vel2: &mut GenericRhs,
        solver_vels: &mut DVector,
    ) {
        let j_id1 = j_id1(j_id, ndofs1, ndofs2);
        let j_id2 = j_id2(j_id, ndofs1, ndofs2);

        solver_vel1.apply_impulse(
            j_id1,
            ndofs1,
            self.impulse,
            jacobians,
            dir1,
            self.ii_torque_dir1,
            solver_vels,
            im1,
        );
        solver_vel2.apply_impulse(
            j_id2,
            ndofs2,
            self.impulse,
            jacobians,
            -dir1,
            self.ii_torque_dir2,
            solver_vels,
            im2,
        );
    }

    #[inline]
    pub fn generic_solve(
        &mut self,
        cfm_factor: Real,
        j_id: usize,
        jacobians: &DVector,
        dir1: Vector,
        im1: Vector,
        im2: Vector,
        ndofs1: usize,
        ndofs2: usize,
        solver_vel1: &mut GenericRhs,
        solver_vel2: &mut GenericRhs,
        solver_vels: &mut DVector,
    ) {
        let j_id1 = j_id1(j_id, ndofs1, ndofs2);
        let j_id2 = j_id2(j_id, ndofs1, ndofs2);

        let dvel = solver_vel1.dvel(
            j_id1,
            ndofs1,
            jacobians,
            dir1,
            self.torque_dir1,
            solver_vels,
        ) + solver_vel2.dvel(
            j_id2,
            ndofs2,
            jacobians,
            -dir1,
            self.torque_dir2,
            solver_vels,
        ) + self.rhs;

        let new_impulse = cfm_factor * (self.impulse - self.r * dvel).max(0.0);
        let dlambda = new_impulse - self.impulse;
        self.impulse = new_impulse;

        solver_vel1.apply_impulse(
            j_id1,
            ndofs1,
            dlambda,
            jacobians,
            dir1,
            self.ii_torque_dir1,
            solver_vels,
            im1,
        );
        solver_vel2.apply_impulse(
            j_id2,
            ndofs2,
            dlambda,
            jacobians,
            -dir1,
            self.ii_torque_dir2,
            solver_vels,
            im2,
        );
    }
}

impl GenericContactConstraint {
    /// gymfleet patch 39 (see `PATCHES.md`): each point's velocity increment along the normal
    /// over a substep (negative when the external forces close it), from the rigid bodies'
    /// `increments` and the multibodies' `generic_increments` (the solver's
    /// `solver_vels_increment` and `generic_solver_vels_increment`).
    pub(crate) fn normal_increments(
        &self,
        jacobians: &DVector,
        increments: &[SolverVel<Real>],
        generic_increments: &DVector,
    ) -> [Real; crate::math::MAX_MANIFOLD_POINTS] {
        self.normal_velocities(jacobians, increments, generic_increments)
    }

    /// Each point's normal velocity `J·v` (positive when separating) under the body
    /// velocities `vels` and the multibodies' `generic_vels` (gymfleet patch 43, from
    /// patch 39's `normal_increments`).
    pub(crate) fn normal_velocities(
        &self,
        jacobians: &DVector,
        increments: &[SolverVel<Real>],
        generic_increments: &DVector,
    ) -> [Real; crate::math::MAX_MANIFOLD_POINTS] {
        let (side1, side2) = self.sides(increments);
        let (ndofs1, ndofs2) = (self.ndofs1, self.ndofs2);
        let j_step = j_step(ndofs1, ndofs2) * DIM;
        let mut out = [0.0; crate::math::MAX_MANIFOLD_POINTS];
        let mut nrm_j_id = normal_j_id(self.j_id, ndofs1, ndofs2);
        for (k, normal_part) in self.normal_part[..self.num_contacts as usize]
            .iter()
            .enumerate()
        {
            out[k] = side1.dvel(
                j_id1(nrm_j_id, ndofs1, ndofs2),
                ndofs1,
                jacobians,
                self.dir1,
                normal_part.torque_dir1,
                generic_increments,
            ) + side2.dvel(
                j_id2(nrm_j_id, ndofs1, ndofs2),
                ndofs2,
                jacobians,
                -self.dir1,
                normal_part.torque_dir2,
                generic_increments,
            );
            nrm_j_id += j_step;
        }
        out
    }

    /// Each point's tangential velocities `J_t·v` along `tangent1` and `normal × tangent1`
    /// (the friction rows' directions), as [`Self::normal_velocities`] (gymfleet patch 43).
    #[cfg(feature = "dim3")]
    pub(crate) fn tangent_velocities(
        &self,
        jacobians: &DVector,
        vels: &[SolverVel<Real>],
        generic_vels: &DVector,
    ) -> [[Real; DIM - 1]; crate::math::MAX_MANIFOLD_POINTS] {
        let (side1, side2) = self.sides(vels);
        let (ndofs1, ndofs2) = (self.ndofs1, self.ndofs2);
        let j_step = j_step(ndofs1, ndofs2);
        let tangents1 = [self.tangent1, self.dir1.cross(self.tangent1)];
        let mut out = [[0.0; DIM - 1]; crate::math::MAX_MANIFOLD_POINTS];
        let mut tng_j_id = tangent_j_id(self.j_id, ndofs1, ndofs2);
        for (k, tangent_part) in self.tangent_part[..self.num_contacts as usize]
            .iter()
            .enumerate()
        {
            for j in 0..DIM - 1 {
                out[k][j] = side1.dvel(
                    j_id1(tng_j_id, ndofs1, ndofs2) + j * j_step,
                    ndofs1,
                    jacobians,
                    tangents1[j],
                    tangent_part.torque_dir1[j],
                    generic_vels,
                ) + side2.dvel(
                    j_id2(tng_j_id, ndofs1, ndofs2) + j * j_step,
                    ndofs2,
                    jacobians,
                    -tangents1[j],
                    tangent_part.torque_dir2[j],
                    generic_vels,
                );
            }
            tng_j_id += j_step * DIM;
        }
        out
    }

    /// gymfleet patch 47: the sides of this constraint under the body velocities `vels`
    /// (the multibodies' read from the generic velocity vector passed beside them).
    pub(crate) fn sides(&self, vels: &[SolverVel<Real>]) -> (GenericRhs, GenericRhs) {
        let side = |solver_vel: u32, mask: u8| {
            if solver_vel == u32::MAX {
                GenericRhs::Fixed
            } else if self.generic_constraint_mask & mask == 0 {
                GenericRhs::SolverVel(vels[solver_vel as usize])
            } else {
                GenericRhs::GenericId(solver_vel)
            }
        };
        (side(self.solver_vel1, 0b01), side(self.solver_vel2, 0b10))
    }

    /// gymfleet patch 47: the first angular friction row's Jacobian index (after every
    /// point's normal and tangent rows) and the distance between two rows.
    pub(crate) fn angular_j_id(&self) -> (usize, usize) {
        let step = j_step(self.ndofs1, self.ndofs2);
        (self.j_id + self.num_contacts as usize * DIM * step, step)
    }

    /// gymfleet patch 47: the angular friction rows' velocities, as
    /// [`Self::tangent_velocities`].
    #[cfg(feature = "dim3")]
    pub(crate) fn angular_velocities(
        &self,
        jacobians: &DVector,
        vels: &[SolverVel<Real>],
        generic_vels: &DVector,
    ) -> [Real; super::MAX_ANGULAR_ROWS] {
        let (side1, side2) = self.sides(vels);
        let (j_id, step) = self.angular_j_id();
        self.angular.velocities(
            0..self.angular.rows as usize,
            j_id,
            step,
            (self.ndofs1, self.ndofs2),
            jacobians,
            (&side1, &side2),
            generic_vels,
        )
    }

    #[inline]
    pub fn generic_warmstart_group(
        normal_parts: &mut [ContactConstraintNormalPart<Real>],
        tangent_parts: &mut [ContactConstraintTangentPart<Real>],
        jacobians: &DVector,
        dir1: Vector,
        #[cfg(feature = "dim3")] tangent1: Vector,
        im1: Vector,
        im2: Vector,
        // ndofs is 0 for a non-multibody body, or a multibody with zero
        // degrees of freedom.
        ndofs1: usize,
        ndofs2: usize,
        // Jacobian index of the first constraint.
        j_id: usize,
        solver_vel1: &mut GenericRhs,
        solver_vel2: &mut GenericRhs,
        solver_vels: &mut DVector,
    ) {
        let j_step = j_step(ndofs1, ndofs2) * DIM;

        // Solve penetration.
        {
            let mut nrm_j_id = normal_j_id(j_id, ndofs1, ndofs2);

            for normal_part in normal_parts {
                normal_part.generic_warmstart(
                    nrm_j_id,
                    jacobians,
                    dir1,
                    im1,
                    im2,
                    ndofs1,
                    ndofs2,
                    solver_vel1,
                    solver_vel2,
                    solver_vels,
                );
                nrm_j_id += j_step;
            }
        }

        // Solve friction.
        {
            #[cfg(feature = "dim3")]
            let tangents1 = [tangent1, dir1.cross(tangent1)];
            #[cfg(feature = "dim2")]
            let tangents1 = [dir1.orthonormal_vector()];
            let mut tng_j_id = tangent_j_id(j_id, ndofs1, ndofs2);

            for tangent_part in tangent_parts {
                tangent_part.generic_warmstart(
                    tng_j_id,
                    jacobians,
                    tangents1,
                    im1,
                    im2,
                    ndofs1,
                    ndofs2,
                    solver_vel1,
                    solver_vel2,
                    solver_vels,
                );
                tng_j_id += j_step;
            }
        }
    }

    #[inline]
    pub fn generic_solve_group(
        cfm_factor: Real,
        compliant: bool,
        tangent_cfm: &[[Real; DIM - 1]],
        pyramid: Option<[Real; 2]>,
        normal_parts: &mut [ContactConstraintNormalPart<Real>],
        tangent_parts: &mut [ContactConstraintTangentPart<Real>],
        jacobians: &DVector,
        dir1: Vector,
        #[cfg(feature = "dim3")] tangent1: Vector,
        im1: Vector,
        im2: Vector,
        limit: Real,
        // ndofs is 0 for a non-multibody body, or a multibody with zero
        // degrees of freedom.
        ndofs1: usize,
        ndofs2: usize,
        // Jacobian index of the first constraint.
        j_id: usize,
        solver_vel1: &mut GenericRhs,
        solver_vel2: &mut GenericRhs,
        solver_vels: &mut DVector,
        solve_restitution: bool,
        solve_friction: bool,
    ) {
        let j_step = j_step(ndofs1, ndofs2) * DIM;

        // Solve penetration.
        if solve_restitution {
            let mut nrm_j_id = normal_j_id(j_id, ndofs1, ndofs2);

            for normal_part in &mut *normal_parts {
                // gymfleet patch 43: a compliant point's own impedance.
                let cfm_factor = if compliant {
                    normal_part.cfm_factor
                } else {
                    cfm_factor
                };
                normal_part.generic_solve(
                    cfm_factor,
                    nrm_j_id,
                    jacobians,
                    dir1,
                    im1,
                    im2,
                    ndofs1,
                    ndofs2,
                    solver_vel1,
                    solver_vel2,
                    solver_vels,
                );
                nrm_j_id += j_step;
            }
        }

        // Solve friction.
        if solve_friction {
            #[cfg(feature = "dim3")]
            let tangents1 = [tangent1, dir1.cross(tangent1)];
            #[cfg(feature = "dim2")]
            let tangents1 = [dir1.orthonormal_vector()];
            let mut tng_j_id = tangent_j_id(j_id, ndofs1, ndofs2);

            for (k, (normal_part, tangent_part)) in
                normal_parts.iter().zip(tangent_parts.iter_mut()).enumerate()
            {
                let limit = limit * normal_part.impulse;
                let cfm = if compliant {
                    tangent_cfm[k]
                } else {
                    [1.0; DIM - 1]
                };
                tangent_part.generic_solve(
                    tng_j_id,
                    jacobians,
                    tangents1,
                    im1,
                    im2,
                    ndofs1,
                    ndofs2,
                    limit,
                    cfm,
                    pyramid,
                    solver_vel1,
                    solver_vel2,
                    solver_vels,
                );
                tng_j_id += j_step;
            }
        }
    }
}

/// gymfleet patch 43: `impulse` (in the constraint's tangent basis) kept in MuJoCo's pyramid
/// section `|f₁| + |f₂| ≤ limit`, `f` its components on MuJoCo's contact-frame axes, which
/// make the angle `[cos, sin]` = `axes` with the basis: the nearest point of that square
/// (Euclidean), as `cap_magnitude` is the nearest point of the circle.
#[cfg(feature = "dim3")]
pub(crate) fn pyramid_section(
    impulse: na::Vector2<Real>,
    axes: [Real; 2],
    limit: Real,
) -> na::Vector2<Real> {
    let [c, s] = axes;
    let (a, b) = (c * impulse.x + s * impulse.y, -s * impulse.x + c * impulse.y);
    let excess = a.abs() + b.abs() - limit.max(0.0);
    if excess <= 0.0 {
        return impulse;
    }
    // Onto the edge of the quadrant, or its corner when that would cross an axis.
    let shift = 0.5 * excess;
    let (mut pa, mut pb) = ((a.abs() - shift).max(0.0), (b.abs() - shift).max(0.0));
    let total = pa + pb;
    if total > limit.max(0.0) {
        // Past the corner: the axis nearer the point keeps the whole limit.
        if a.abs() >= b.abs() {
            (pa, pb) = (limit.max(0.0), 0.0);
        } else {
            (pa, pb) = (0.0, limit.max(0.0));
        }
    }
    let (pa, pb) = (pa.copysign(a), pb.copysign(b));
    na::Vector2::new(c * pa - s * pb, s * pa + c * pb)
}
