//! gymfleet patch 47 (see `PATCHES.md`): MuJoCo's torsional and rolling friction (`condim`
//! 4 and 6) on a compliant generic contact.
//!
//! A manifold of `condim` 4 gets one angular row about its normal (torsional friction), one
//! of `condim` 6 two more about its tangents (rolling friction). An angular row's Jacobian
//! does not depend on where the contact point is, so one row per manifold, bounded by its
//! coefficient times the manifold's summed normal impulse, is the sum of MuJoCo's per-point
//! rows (each bounded by its own point's normal force). The rows are regularised as MuJoCo's
//! (`PairCompliance::angular_row`) and solved after the sliding rows; the torsional row is
//! kept in `|τ| ≤ μ_t·λₙ`, the rolling pair in the pyramid's section (or the ellipse's
//! circle) `|r₁| + |r₂| ≤ μ_r·λₙ`, each group apart from the others (MuJoCo's cones couple
//! all of a contact's friction directions).

use super::generic_contact_constraint_element::GenericRhs;
use crate::math::{AngVector, DVector, Real, Vector};

/// At most: one torsional and two rolling rows.
pub(crate) const MAX_ANGULAR_ROWS: usize = 3;

/// A generic contact's angular friction rows (gymfleet patch 47).
#[derive(Copy, Clone, Debug)]
pub(crate) struct AngularFrictionPart {
    /// How many rows are in use: 0, 1 (`condim` 4) or 3 (`condim` 6).
    pub rows: u8,
    /// Each row's axis in world space (body 1 turns about it, body 2 about its opposite).
    pub axes: [Vector; MAX_ANGULAR_ROWS],
    /// Each row's friction coefficient (m).
    pub mu: [Real; MAX_ANGULAR_ROWS],
    pub ii_torque_dir1: [AngVector; MAX_ANGULAR_ROWS],
    pub ii_torque_dir2: [AngVector; MAX_ANGULAR_ROWS],
    /// Each row's effective mass `1/(J·M⁻¹·Jᵀ)`.
    pub r: [Real; MAX_ANGULAR_ROWS],
    pub rhs: [Real; MAX_ANGULAR_ROWS],
    pub cfm: [Real; MAX_ANGULAR_ROWS],
    pub impulse: [Real; MAX_ANGULAR_ROWS],
}

impl AngularFrictionPart {
    pub fn zero() -> Self {
        Self {
            rows: 0,
            axes: [Vector::ZERO; MAX_ANGULAR_ROWS],
            mu: [0.0; MAX_ANGULAR_ROWS],
            ii_torque_dir1: [AngVector::ZERO; MAX_ANGULAR_ROWS],
            ii_torque_dir2: [AngVector::ZERO; MAX_ANGULAR_ROWS],
            r: [0.0; MAX_ANGULAR_ROWS],
            rhs: [0.0; MAX_ANGULAR_ROWS],
            cfm: [1.0; MAX_ANGULAR_ROWS],
            impulse: [0.0; MAX_ANGULAR_ROWS],
        }
    }

    /// The velocities `J·v` of rows `rows` under the body velocities of `side1` and `side2`,
    /// the rows' Jacobians from `j_id` on, `j_step` apart (the others are left at zero).
    #[allow(clippy::too_many_arguments)]
    pub fn velocities(
        &self,
        rows: core::ops::Range<usize>,
        j_id: usize,
        j_step: usize,
        ndofs: (usize, usize),
        jacobians: &DVector,
        sides: (&GenericRhs, &GenericRhs),
        generic_vels: &DVector,
    ) -> [Real; MAX_ANGULAR_ROWS] {
        let mut out = [0.0; MAX_ANGULAR_ROWS];
        for j in rows {
            let v = &mut out[j];
            let row = j_id + j * j_step;
            *v = sides.0.dvel(
                row,
                ndofs.0,
                jacobians,
                Vector::ZERO,
                self.axes[j],
                generic_vels,
            ) + sides.1.dvel(
                row + ndofs.0 * 2,
                ndofs.1,
                jacobians,
                Vector::ZERO,
                -self.axes[j],
                generic_vels,
            );
        }
        out
    }

    fn apply(
        &self,
        j: usize,
        row: usize,
        impulse: Real,
        ndofs: (usize, usize),
        jacobians: &DVector,
        sides: (&mut GenericRhs, &mut GenericRhs),
        solver_vels: &mut DVector,
    ) {
        sides.0.apply_impulse(
            row,
            ndofs.0,
            impulse,
            jacobians,
            Vector::ZERO,
            self.ii_torque_dir1[j],
            solver_vels,
            Vector::ZERO,
        );
        sides.1.apply_impulse(
            row + ndofs.0 * 2,
            ndofs.1,
            impulse,
            jacobians,
            Vector::ZERO,
            self.ii_torque_dir2[j],
            solver_vels,
            Vector::ZERO,
        );
    }

    /// Applies the rows' impulses (the warm start of a substep).
    pub fn warmstart(
        &self,
        j_id: usize,
        j_step: usize,
        ndofs: (usize, usize),
        jacobians: &DVector,
        sides: (&mut GenericRhs, &mut GenericRhs),
        solver_vels: &mut DVector,
    ) {
        let (s1, s2) = sides;
        for j in 0..self.rows as usize {
            self.apply(
                j,
                j_id + j * j_step,
                self.impulse[j],
                ndofs,
                jacobians,
                (&mut *s1, &mut *s2),
                solver_vels,
            );
        }
    }

    /// One projected Gauss–Seidel sweep of the rows, the manifold's summed normal impulse
    /// `normal` bounding them; the rolling pair is kept in the pyramid's section about `axes`
    /// (MuJoCo's contact frame in the rows' tangent basis) or, without, in the circle.
    #[allow(clippy::too_many_arguments)]
    pub fn solve(
        &mut self,
        j_id: usize,
        j_step: usize,
        ndofs: (usize, usize),
        jacobians: &DVector,
        normal: Real,
        pyramid: Option<[Real; 2]>,
        sides: (&mut GenericRhs, &mut GenericRhs),
        solver_vels: &mut DVector,
    ) {
        let (s1, s2) = sides;
        let rows = self.rows as usize;
        let mut new = [0.0; MAX_ANGULAR_ROWS];
        // The rolling pair is solved as a pair (both from the same velocities), as the
        // sliding rows are.
        let groups: &[core::ops::Range<usize>] = if rows == 3 { &[0..1, 1..3] } else { &[0..1] };
        for group in groups.iter().filter(|g| g.end <= rows) {
            // Only the group's own rows: the torsional row's velocity is not read again.
            let vels = self.velocities(
                group.clone(),
                j_id,
                j_step,
                ndofs,
                jacobians,
                (&*s1, &*s2),
                solver_vels,
            );
            for j in group.clone() {
                new[j] = self.cfm[j] * (self.impulse[j] - self.r[j] * (vels[j] + self.rhs[j]));
            }
            if group.len() == 1 {
                let j = group.start;
                let limit = (self.mu[j] * normal).max(0.0);
                new[j] = new[j].clamp(-limit, limit);
            } else {
                let limit = (self.mu[1] * normal).max(0.0);
                let pair = na::Vector2::new(new[1], new[2]);
                let pair = match pyramid {
                    Some(axes) => super::generic_contact_constraint_element::pyramid_section(
                        pair, axes, limit,
                    ),
                    None => pair.cap_magnitude(limit),
                };
                (new[1], new[2]) = (pair.x, pair.y);
            }
            for j in group.clone() {
                let dlambda = new[j] - self.impulse[j];
                self.impulse[j] = new[j];
                self.apply(
                    j,
                    j_id + j * j_step,
                    dlambda,
                    ndofs,
                    jacobians,
                    (&mut *s1, &mut *s2),
                    solver_vels,
                );
            }
        }
    }
}
