//! gymfleet patch 51 (see `PATCHES.md`): MuJoCo's
//! pyramidal friction cone as its facets, on a compliant generic contact of `condim` 3.
//!
//! MuJoCo solves a pyramidal contact as four facet rows `J_n ± μ·J_a`, `J_n ± μ·J_b` (`a`,
//! `b` its contact frame's tangents), each pushing only (`λ ≥ 0`), each regularised by
//! `R_py` and pulled to its own reference acceleration `−B·v_f − K·d·r` (`v_f` the facet's
//! velocity, `r` the contact's depth): the normal force is the facets' sum, the friction
//! `μ` times their differences. A sliding contact's facet against the motion then closes
//! fast (`v_n − μ·v_t`), and its reference pushes the bodies apart as well as back: MuJoCo's
//! sliding bodies ride up on their contacts, which the normal row and two friction rows kept
//! in the pyramid's section do not reproduce. The facets are solved here with each point's
//! 3×3 coupling `A` of its normal and tangent rows (exact for the point's own rows), their
//! impulses folded back into the normal and tangent impulses (the write-back and the contact
//! forces read back are unchanged). They start from zero at every step (no warm start).

use super::generic_contact_constraint_element::{GenericRhs, j_step};
use super::GenericContactConstraint;
use crate::math::{DIM, DVector, MAX_MANIFOLD_POINTS, Real};
use crate::utils::{ComponentMul, DotProduct};

/// At most this many Gauss–Seidel sweeps over one point's facets per solver sweep; they stop
/// once a sweep changes the facets' impulses by at most [`LOCAL_TOLERANCE`] of their sum.
const LOCAL_SWEEPS: usize = 32;
const LOCAL_TOLERANCE: Real = 1.0e-5;

/// A compliant pyramid's facets (gymfleet patch 51).
#[derive(Copy, Clone, Debug)]
pub(crate) struct FacetPart {
    /// Whether the constraint is solved by its facets.
    pub active: bool,
    /// Each facet's tangent part `μ·e_f` in the constraint's tangent basis: `+a`, `−a`,
    /// `+b`, `−b` of MuJoCo's contact frame.
    pub dirs: [[Real; 2]; 4],
    /// Each point's `A` over its normal and two tangent rows: `nn, n1, n2, 11, 12, 22`.
    pub a: [[Real; 6]; MAX_MANIFOLD_POINTS],
    pub rhs: [[Real; 4]; MAX_MANIFOLD_POINTS],
    /// `1/(A_f + R_py)` of each facet (0: the facet pushes nothing).
    pub inv: [[Real; 4]; MAX_MANIFOLD_POINTS],
    /// Each point's `R_py`.
    pub reg: [Real; MAX_MANIFOLD_POINTS],
    pub lambda: [[Real; 4]; MAX_MANIFOLD_POINTS],
}

impl FacetPart {
    pub fn zero() -> Self {
        Self {
            active: false,
            dirs: [[0.0; 2]; 4],
            a: [[0.0; 6]; MAX_MANIFOLD_POINTS],
            rhs: [[0.0; 4]; MAX_MANIFOLD_POINTS],
            inv: [[0.0; 4]; MAX_MANIFOLD_POINTS],
            reg: [0.0; MAX_MANIFOLD_POINTS],
            lambda: [[0.0; 4]; MAX_MANIFOLD_POINTS],
        }
    }

    /// The facets' tangent parts for friction `mu` and MuJoCo's contact frame at
    /// `[cos, sin]` = `axes` in the constraint's tangent basis.
    pub fn directions(mu: Real, axes: [Real; 2]) -> [[Real; 2]; 4] {
        let [c, s] = axes;
        [
            [mu * c, mu * s],
            [-mu * c, -mu * s],
            [-mu * s, mu * c],
            [mu * s, -mu * c],
        ]
    }

    /// `J_f·M⁻¹·J_fᵀ` of facet `f` of point `k`.
    pub fn facet_a(&self, k: usize, f: usize) -> Real {
        let [nn, n1, n2, t11, t12, t22] = self.a[k];
        let [e1, e2] = self.dirs[f];
        nn + 2.0 * (e1 * n1 + e2 * n2) + e1 * e1 * t11 + 2.0 * e1 * e2 * t12 + e2 * e2 * t22
    }

    /// Splits point `k`'s normal impulse `n` and tangent impulse `t` (the warm start) over
    /// its facets, each at least zero, and returns the impulses they add up to.
    pub fn split(&mut self, k: usize, n: Real, t: [Real; 2]) -> (Real, [Real; 2]) {
        let n = n.max(0.0);
        let mut lambda = [0.0; 4];
        for (pair, l) in lambda.chunks_mut(2).enumerate() {
            let [e1, e2] = self.dirs[2 * pair];
            let mu2 = e1 * e1 + e2 * e2;
            // The pair's friction along its direction, in impulse per unit facet impulse.
            let along = if mu2 > 0.0 { (t[0] * e1 + t[1] * e2) / mu2 } else { 0.0 };
            l[0] = (0.25 * n + 0.5 * along).max(0.0);
            l[1] = (0.25 * n - 0.5 * along).max(0.0);
        }
        self.lambda[k] = lambda;
        let mut total_n = 0.0;
        let mut total_t = [0.0; 2];
        for (f, l) in lambda.iter().enumerate() {
            total_n += l;
            total_t[0] += l * self.dirs[f][0];
            total_t[1] += l * self.dirs[f][1];
        }
        (total_n, total_t)
    }
}

impl GenericContactConstraint {
    /// gymfleet patch 51: point `k`'s coupling `A` of its normal and tangent rows (see
    /// [`FacetPart::a`]), from the rigid bodies' masses or the multibodies' Jacobians.
    pub(crate) fn facet_coupling(&self, jacobians: &DVector, k: usize) -> [Real; 6] {
        let (ndofs1, ndofs2) = (self.ndofs1, self.ndofs2);
        let step = j_step(ndofs1, ndofs2);
        let nrm = self.j_id + k * DIM * step;
        let rows = [nrm, nrm + step, nrm + 2 * step];
        let tangents = [self.tangent1, self.dir1.cross(self.tangent1)];
        let lin = [self.dir1, tangents[0], tangents[1]];
        let normal = &self.normal_part[k];
        let tangent = &self.tangent_part[k];
        let torque1 = [normal.torque_dir1, tangent.torque_dir1[0], tangent.torque_dir1[1]];
        let ii1 = [normal.ii_torque_dir1, tangent.ii_torque_dir1[0], tangent.ii_torque_dir1[1]];
        let torque2 = [normal.torque_dir2, tangent.torque_dir2[0], tangent.torque_dir2[1]];
        let ii2 = [normal.ii_torque_dir2, tangent.ii_torque_dir2[0], tangent.ii_torque_dir2[1]];
        let side = |x: usize, y: usize, first: bool| -> Real {
            let (solver_vel, mask, ndofs, offset) = if first {
                (self.solver_vel1, 0b01, ndofs1, 0)
            } else {
                (self.solver_vel2, 0b10, ndofs2, 2 * ndofs1)
            };
            if solver_vel == u32::MAX {
                0.0
            } else if self.generic_constraint_mask & mask == 0 {
                let (im, torque, ii, sign) = if first {
                    (self.im1, &torque1, &ii1, 1.0)
                } else {
                    (self.im2, &torque2, &ii2, -1.0)
                };
                let (dx, dy) = (lin[x] * sign, lin[y] * sign);
                dx.dot(dy.component_mul(&im)) + ii[x].gdot(torque[y])
            } else if ndofs == 0 {
                0.0
            } else {
                let j = jacobians.rows(rows[x] + offset, ndofs);
                let wj = jacobians.rows(rows[y] + offset + ndofs, ndofs);
                j.dot(&wj)
            }
        };
        let a = |x: usize, y: usize| side(x, y, true) + side(x, y, false);
        [a(0, 0), a(0, 1), a(0, 2), a(1, 1), a(1, 2), a(2, 2)]
    }

    /// gymfleet patch 51: one Gauss–Seidel sweep of every point's facets.
    pub(crate) fn solve_facets(
        &mut self,
        jacobians: &DVector,
        side1: &mut GenericRhs,
        side2: &mut GenericRhs,
        solver_vels: &mut DVector,
    ) {
        let (ndofs1, ndofs2) = (self.ndofs1, self.ndofs2);
        let step = j_step(ndofs1, ndofs2);
        let tangents = [self.tangent1, self.dir1.cross(self.tangent1)];
        let lin = [self.dir1, tangents[0], tangents[1]];
        for k in 0..self.num_contacts as usize {
            let nrm = self.j_id + k * DIM * step;
            let rows = [nrm, nrm + step, nrm + 2 * step];
            let (torque1, ii1, torque2, ii2) = {
                let n = &self.normal_part[k];
                let t = &self.tangent_part[k];
                (
                    [n.torque_dir1, t.torque_dir1[0], t.torque_dir1[1]],
                    [n.ii_torque_dir1, t.ii_torque_dir1[0], t.ii_torque_dir1[1]],
                    [n.torque_dir2, t.torque_dir2[0], t.torque_dir2[1]],
                    [n.ii_torque_dir2, t.ii_torque_dir2[0], t.ii_torque_dir2[1]],
                )
            };
            // The point's row velocities, then kept up to date through `A`.
            let mut v = [0.0; 3];
            for x in 0..3 {
                v[x] = side1.dvel(rows[x], ndofs1, jacobians, lin[x], torque1[x], solver_vels)
                    + side2.dvel(
                        rows[x] + ndofs1 * 2,
                        ndofs2,
                        jacobians,
                        -lin[x],
                        torque2[x],
                        solver_vels,
                    );
            }
            let [nn, n1, n2, t11, t12, t22] = self.facet.a[k];
            let coupling = [[nn, n1, n2], [n1, t11, t12], [n2, t12, t22]];
            let mut delta = [0.0; 3];
            // The point's four facets share its normal: Gauss–Seidel over them alone (its
            // own rows, through `A`, no body touched) until they settle.
            for _ in 0..LOCAL_SWEEPS {
                let (mut change, mut size) = (0.0, 0.0);
                for f in 0..4 {
                    let inv = self.facet.inv[k][f];
                    if inv <= 0.0 {
                        continue;
                    }
                    let c = [1.0, self.facet.dirs[f][0], self.facet.dirs[f][1]];
                    let vf = v[0] + c[1] * v[1] + c[2] * v[2];
                    let lambda = self.facet.lambda[k][f];
                    let residual = vf + self.facet.rhs[k][f] + self.facet.reg[k] * lambda;
                    let new = (lambda - inv * residual).max(0.0);
                    let dl = new - lambda;
                    size += new;
                    if dl == 0.0 {
                        continue;
                    }
                    change += dl.abs();
                    self.facet.lambda[k][f] = new;
                    for x in 0..3 {
                        delta[x] += c[x] * dl;
                        v[x] += (coupling[x][0] + coupling[x][1] * c[1] + coupling[x][2] * c[2])
                            * dl;
                    }
                }
                if change <= LOCAL_TOLERANCE * size {
                    break;
                }
            }
            self.normal_part[k].impulse += delta[0];
            self.tangent_part[k].impulse[0] += delta[1];
            self.tangent_part[k].impulse[1] += delta[2];
            for x in 0..3 {
                if delta[x] == 0.0 {
                    continue;
                }
                side1.apply_impulse(
                    rows[x],
                    ndofs1,
                    delta[x],
                    jacobians,
                    lin[x],
                    ii1[x],
                    solver_vels,
                    self.im1,
                );
                side2.apply_impulse(
                    rows[x] + ndofs1 * 2,
                    ndofs2,
                    delta[x],
                    jacobians,
                    -lin[x],
                    ii2[x],
                    solver_vels,
                    self.im2,
                );
            }
        }
    }
}

/// The facet rows' targets need the rows' velocities at the substep's start: a facet's is
/// its normal's plus its tangent part's.
pub(crate) fn facet_velocity(dirs: [Real; 2], normal: Real, tangent: [Real; DIM - 1]) -> Real {
    normal + dirs[0] * tangent[0] + dirs[1] * tangent[1]
}
