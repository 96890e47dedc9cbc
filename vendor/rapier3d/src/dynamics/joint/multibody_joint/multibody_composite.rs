//! The multibody mass matrices by composite rigid bodies (gymfleet patch, see `PATCHES.md`).
//!
//! `Multibody::update_mass_matrix` builds `M = Σᵢ Jᵢᵀ·diag(mᵢ, Iᵢ)·Jᵢ` and the velocity terms of
//! the semi-implicit matrix, `D = ∂τ_bias/∂q̇` (the derivative of the coriolis, centrifugal and
//! gyroscopic generalized forces), link by link: for a chain of `n` links that is `O(n³)` work.
//! For a multibody whose root is fixed or free and whose other joints have at most one DoF each
//! (arms, chains, the slide/hinge roots MJCF imports use, and floating robots such as the Ant
//! and the Humanoid), this module builds the same two matrices in `O(n·depth)` with spatial
//! algebra; where the velocity terms are left out, it builds `M` for joints of any number of
//! DoFs (ball, cylindrical, planar: patch 30), and with them both matrices for planar joints
//! (patch 31):
//!
//! - every spatial vector is taken at one point `p₀` (the root link's centre of mass) in world
//!   axes, in `f64` so that the lever arms of a long chain cost no precision; a motion vector is
//!   `(ω, v)` (`v` the velocity of the point at `p₀`), a force `(n, f)` (`n` the moment about
//!   `p₀`);
//! - DoF `c` of link `L` moves every link of `L`'s subtree by the same motion `S_c` (its column
//!   of `L`'s body jacobian, taken to `p₀`);
//! - `M[a, c] = S_a · Î_L S_c` for `a` on the path from the root to `L`, with `Î_L` the spatial
//!   inertia of `L`'s whole subtree (the composite rigid-body algorithm);
//! - with `Vᵢ` link `i`'s spatial velocity and `λ` the parent of `L`, the force each link of the
//!   subtree adds per unit `q̇_c` is `Iᵢ·(2V_λ − Vᵢ)×S_c + S_c×*(IᵢVᵢ) + Vᵢ×*(IᵢS_c)`, which sums
//!   over a subtree `K` to `Î_K·(2V_λ×S_c) + B̂_K·S_c + S_c×*Ĥ_K`, with `Ĥ_K = Σ IᵢVᵢ` and
//!   `B̂_K = Σ ([Vᵢ×*]·Iᵢ − Iᵢ·[Vᵢ×])` (symmetric). `D[a, c]` is `S_a` dotted with it, over the
//!   subtree of the deeper of the two links.
//! - a free root's six DoFs move the whole multibody: the velocity of the root's body-frame
//!   origin `o` and its rotation about `o`. As `o` moves, a rotation's motion at `p₀` changes,
//!   so the root adds the bias acceleration `(0, v_o × ω)`; in the sum above its DoF `c` has
//!   `V_root × S_c + ∂(0, v_o × ω)/∂q̇_c` where a hinge has `2V_λ × S_c`.
//! - a joint of several DoFs below the root (Rapier's: slides along axes fixed in the parent,
//!   then rotations about axes fixed in the parent through the slid anchor) has `U`, the velocity
//!   its slides give, and `V_L = V_λ + U + W` (`W` its rotations'). A rotation's column then also
//!   changes with the slides (`Ṡ_c = (V_λ + U) × S_c`), and a slide moves the anchor the joint's
//!   rotations turn about, so a rotation `c` has `(V_λ + U + V_L) × S_c` where a hinge has
//!   `2V_λ × S_c`; a slide keeps `2V_λ × S_c`. Only planar joints (two slides or more, one
//!   rotation at most) take it with the velocity terms (patch 31).
//!
//! `composite_tests` (in `multibody.rs`) checks `M` against the link-by-link construction and
//! `D` against the derivative, by central differences, of the forces `update_acceleration`
//! applies.

use super::Multibody;
use crate::alloc_prelude::*;
use crate::dynamics::{MultibodyJoint, RigidBody, RigidBodySet};
use crate::glamx::{DMat3, DVec3};
use crate::math::{AngularInertia, DIM, Real, SPATIAL_DIM, Vector};
use crate::utils::AngularInertiaOps;

/// A motion `(ω, v)` or a force `(n, f)` at `p₀`.
#[derive(Copy, Clone, Debug, Default)]
pub(super) struct Spatial {
    ang: DVec3,
    lin: DVec3,
}

impl Spatial {
    fn new(ang: DVec3, lin: DVec3) -> Self {
        Self { ang, lin }
    }

    /// `self · other`, a motion with a force.
    fn dot(self, other: Spatial) -> f64 {
        self.ang.dot(other.ang) + self.lin.dot(other.lin)
    }

    /// The motion cross product `self × m`.
    fn cross_motion(self, m: Spatial) -> Spatial {
        Spatial::new(
            self.ang.cross(m.ang),
            self.ang.cross(m.lin) + self.lin.cross(m.ang),
        )
    }

    /// The force cross product `self ×* f`.
    fn cross_force(self, f: Spatial) -> Spatial {
        Spatial::new(
            self.ang.cross(f.ang) + self.lin.cross(f.lin),
            self.ang.cross(f.lin),
        )
    }

    fn add(self, other: Spatial) -> Spatial {
        Spatial::new(self.ang + other.ang, self.lin + other.lin)
    }

    fn sub(self, other: Spatial) -> Spatial {
        Spatial::new(self.ang - other.ang, self.lin - other.lin)
    }
}

/// A subtree's spatial inertia at `p₀`: its mass, first moment `m·r` and rotational inertia
/// about `p₀`. All that `M` reads.
#[derive(Copy, Clone, Debug, Default)]
pub(super) struct SubtreeInertia {
    mass: f64,
    moment: DVec3,
    inertia: DMat3,
}

impl SubtreeInertia {
    /// One link's, its centre of mass at `r` from `p₀`.
    #[inline(always)]
    fn of_link((mass, inertia): (Vector, AngularInertia), r: DVec3) -> Self {
        let mass = f64::from(mass.x);
        let inertia_com = inertia.into_matrix().as_dmat3();
        let moment = r * mass;
        let inertia = inertia_com + DMat3::from_diagonal(DVec3::splat(mass * r.length_squared()))
            - DMat3::from_cols(moment * r.x, moment * r.y, moment * r.z);
        Self {
            mass,
            moment,
            inertia,
        }
    }

    /// `Î·s`.
    #[inline(always)]
    fn times(&self, s: Spatial) -> Spatial {
        Spatial::new(
            self.inertia * s.ang + self.moment.cross(s.lin),
            self.mass * s.lin - self.moment.cross(s.ang),
        )
    }

    #[inline(always)]
    fn accumulate(&mut self, other: &SubtreeInertia) {
        self.mass += other.mass;
        self.moment += other.moment;
        self.inertia += other.inertia;
    }
}

/// A subtree's spatial inertia at `p₀` with what the velocity terms read: its momentum `Ĥ` and
/// its `B̂` (of which only the upper-left block and the linear momentum, `Ĥ.lin`, are not zero:
/// `B̂ = [[B₁₁, [p]×], [−[p]×, 0]]`).
#[derive(Copy, Clone, Debug, Default)]
pub(super) struct Composite {
    rigid: SubtreeInertia,
    momentum: Spatial,
    b11: DMat3,
}

impl Composite {
    /// `Î·s`.
    fn inertia_times(&self, s: Spatial) -> Spatial {
        self.rigid.times(s)
    }

    /// `B̂·s`.
    fn b_times(&self, s: Spatial) -> Spatial {
        let p = self.momentum.lin;
        Spatial::new(self.b11 * s.ang + p.cross(s.lin), -p.cross(s.ang))
    }

    /// Adds `other`'s inertia, momentum and `B̂`.
    fn accumulate(&mut self, other: &Composite) {
        self.rigid.accumulate(&other.rigid);
        self.momentum = self.momentum.add(other.momentum);
        self.b11 += other.b11;
    }
}

/// What the composite construction needs per DoF beyond its motion `S` and `Î_L·S` (`L` the
/// DoF's link), with the velocity terms only.
#[derive(Copy, Clone, Debug, Default)]
pub(super) struct CompositeDof {
    /// `2·V_λ × S`.
    coriolis_motion: Spatial,
    /// The subtree's force per unit velocity of this DoF:
    /// `Î_L·(2V_λ×S) + B̂_L·S + S×*Ĥ_L`.
    velocity_force: Spatial,
    /// `B̂_L·S − S×*Ĥ_L`, what a DoF below `L` pairs with this one's motion.
    velocity_force_below: Spatial,
}

/// Reused buffers of the composite construction.
#[derive(Clone, Debug, Default)]
pub(crate) struct CompositeWorkspace {
    composites: Vec<Composite>,
    /// The subtrees' inertias alone, where only `M` is built.
    inertias: Vec<SubtreeInertia>,
    velocities: Vec<Spatial>,
    /// Per DoF: its motion `S` and `Î_L·S`, read by every pair, apart from the rest
    /// ([`CompositeDof`], velocity terms only) so that the pairs of `M` read no more. `M` alone
    /// writes and reads only `S`.
    motions: Vec<(Spatial, Spatial)>,
    dofs: Vec<CompositeDof>,
    /// Per link: its parent, its DoFs (none for a welded link or a fixed root) and its
    /// centre of mass relative to `p₀`.
    parents: Vec<usize>,
    offsets: Vec<DVec3>,
    link_dofs: Vec<core::ops::Range<usize>>,
}

impl CompositeWorkspace {
    /// Calls `f` with each buffer's `(address, bytes)` (gymfleet patch 37, see `PATCHES.md`).
    pub(super) fn buffers(&self, f: &mut impl FnMut((usize, usize))) {
        use crate::pipeline::slice_span;
        f(slice_span(&self.composites));
        f(slice_span(&self.inertias));
        f(slice_span(&self.velocities));
        f(slice_span(&self.motions));
        f(slice_span(&self.dofs));
        f(slice_span(&self.parents));
        f(slice_span(&self.offsets));
        f(slice_span(&self.link_dofs));
    }
}

fn dvec3_at(slice: &[Real], at: usize) -> DVec3 {
    DVec3::new(
        f64::from(slice[at]),
        f64::from(slice[at + 1]),
        f64::from(slice[at + 2]),
    )
}

/// `[a]×[b]× + [b]×[a]× = a·bᵀ + b·aᵀ − 2(a·b)·1`.
fn symmetric_cross_product(a: DVec3, b: DVec3) -> DMat3 {
    let outer = |u: DVec3, v: DVec3| DMat3::from_cols(u * v.x, u * v.y, u * v.z);
    outer(a, b) + outer(b, a) - DMat3::from_diagonal(DVec3::splat(2.0 * a.dot(b)))
}

/// A joint of at least two slides and at most one rotation (a planar joint: MJCF's
/// slide/slide/hinge roots as one joint). With the velocity terms, the composite construction
/// takes these among the joints of several DoFs (patch 31); ball and cylindrical joints keep the
/// link-by-link one, and with it their trajectories (upstream's terms for them are not the
/// derivative of the forces either, but moving them is not this patch's business).
fn is_planar(joint: &MultibodyJoint) -> bool {
    let locked = joint.data.locked_axes.bits();
    let free_linear = DIM as u32 - (locked & 0b111).count_ones();
    let free_angular = DIM as u32 - ((locked >> DIM) & 0b111).count_ones();
    free_linear >= 2 && free_angular <= 1
}

impl Multibody {
    /// Whether [`Multibody::composite_mass_matrices`] applies: a root that is fixed or free
    /// (all six DoFs, none locked), other joints of at most one DoF, none kinematic, and
    /// links whose effective mass is the same along every axis. Without `velocity_terms` (only
    /// `M` is built) the other joints may have several DoFs (gymfleet patch 30): each DoF's
    /// more. With `velocity_terms`, planar joints ([`is_planar`]) may too (gymfleet patch 31:
    /// their columns change with their own motion, which the module documentation derives);
    /// ball and cylindrical joints keep the link-by-link construction.
    #[cfg(test)]
    pub(super) fn composite_applies(&self, bodies: &RigidBodySet, velocity_terms: bool) -> bool {
        self.composite_applies_for(velocity_terms, |_, link| {
            bodies[link.rigid_body].mprops.effective_mass()
        })
    }

    /// [`Self::composite_applies`] with `workspace.link_inertias` current (gymfleet patch 35).
    pub(super) fn composite_applies_at_link_inertias(&self, velocity_terms: bool) -> bool {
        self.composite_applies_for(velocity_terms, |i, _| self.workspace.link_inertias[i].0)
    }

    fn composite_applies_for(
        &self,
        velocity_terms: bool,
        mass_of: impl Fn(usize, &super::MultibodyLink) -> Vector,
    ) -> bool {
        let isotropic = |i: usize, link: &super::MultibodyLink| {
            let mass = mass_of(i, link);
            mass.x == mass.y && mass.y == mass.z
        };
        let root = &self.links[0];
        let root_fits = !self.root_is_dynamic
            || (root.joint.ndofs() == SPATIAL_DIM && !root.joint.kinematic && isotropic(0, root));
        root_fits
            && self.links.iter().enumerate().skip(1).all(|(i, link)| {
                (link.joint.ndofs() <= 1 || !velocity_terms || is_planar(&link.joint))
                    && !link.joint.kinematic
                    && isotropic(i, link)
            })
    }

    /// Writes the upper triangle of `M` into `augmented_mass` and all of `dt·D` into
    /// `acc_augmented_mass` (both zeroed by the caller), as the link-by-link construction would;
    /// without `velocity_terms`, `M` alone in both triangles ([`Self::composite_mass_matrix`]).
    /// See the module documentation. Needs the links' poses, body jacobians and velocities of
    /// this configuration (`forward_kinematics`, `update_velocities`), and
    /// `workspace.link_inertias` current.
    pub(super) fn composite_mass_matrices(
        &mut self,
        dt: Real,
        velocity_terms: bool,
        bodies: &RigidBodySet,
    ) {
        if !velocity_terms {
            self.composite_mass_matrix(bodies);
            return;
        }
        let nlinks = self.links.len();
        let mut ws = core::mem::take(&mut self.composite_workspace);
        // Every entry a pass reads is written below (a fixed root's are reset to zero), so the
        // buffers are only resized, not cleared, from one substep to the next.
        ws.composites.resize(nlinks, Composite::default());
        ws.velocities.resize(nlinks, Spatial::default());
        ws.motions.resize(self.ndofs, Default::default());
        ws.dofs.resize(self.ndofs, CompositeDof::default());
        ws.parents.clear();
        ws.link_dofs.clear();
        ws.offsets.clear();
        // Centres of mass from the links' poses, as the body jacobians' shifts are.
        let com = |link: &super::MultibodyLink| {
            let local_com = bodies[link.rigid_body].mprops.local_mprops.local_com;
            (link.local_to_world * local_com).as_dvec3()
        };
        let p0 = com(&self.links[0]);
        for link in self.links.iter() {
            ws.offsets.push(com(link) - p0);
            ws.parents.push(link.parent_internal_id);
            ws.link_dofs
                .push(link.assembly_id..link.assembly_id + link.joint.ndofs());
        }
        // A fixed root is moved by no DoF: it adds to no composite that a DoF reads.
        let first_moving = if self.root_is_dynamic { 0 } else { 1 };
        if first_moving == 1 {
            ws.composites[0] = Composite::default();
            ws.velocities[0] = Spatial::default();
            for c in ws.link_dofs[0].clone() {
                ws.motions[c] = Default::default();
                ws.dofs[c] = CompositeDof::default();
            }
        }

        // Each moving link's own inertia, velocity, momentum and `B` at `p₀`.
        for i in first_moving..nlinks {
            let rb = &bodies[self.links[i].rigid_body];
            let r = ws.offsets[i];
            let mut own = Composite {
                rigid: SubtreeInertia::of_link(self.workspace.link_inertias[i], r),
                ..Composite::default()
            };
            let angvel = rb.vels.angvel.as_dvec3();
            let velocity = Spatial::new(angvel, rb.vels.linvel.as_dvec3() - angvel.cross(r));
            ws.velocities[i] = velocity;
            own.momentum = own.inertia_times(velocity);
            // B₁₁ = [ω]×·I − I·[ω]× − ([v]×[h]× + [h]×[v]×), where I·[ω]× = −([ω]×·I)ᵀ
            // since I is symmetric.
            let w = angvel;
            let omega = DMat3::from_cols(
                DVec3::new(0.0, w.z, -w.y),
                DVec3::new(-w.z, 0.0, w.x),
                DVec3::new(w.y, -w.x, 0.0),
            );
            let omega_inertia = omega * own.rigid.inertia;
            own.b11 = omega_inertia + omega_inertia.transpose()
                - symmetric_cross_product(velocity.lin, own.rigid.moment);
            ws.composites[i] = own;
        }

        // Subtree sums, children (which come after their parents) first.
        for i in (1..nlinks).rev() {
            let parent = self.links[i].parent_internal_id;
            let (above, from_child) = ws.composites.split_at_mut(i);
            above[parent].accumulate(&from_child[0]);
        }

        // A free root's DoFs: the velocity of its body frame's origin along the axes `b_j`
        // and its rotation about that origin along `a_k` (`root_shift23`). The origin moves,
        // so a rotation's motion at `p₀` changes with the linear DoFs: the root adds the
        // bias acceleration `(0, v_o × ω)` (`v_o = Σ b_j·q̇_j`, `ω = Σ a_k·q̇_k`), whose
        // derivative is `(0, b_j × ω)` for a linear DoF and `(0, v_o × a_k)` for a rotation.
        let (mut root_origin_velocity, mut root_angvel) = (DVec3::ZERO, DVec3::ZERO);
        if self.root_is_dynamic {
            let jacobian = self.body_jacobians[0].as_slice();
            for c in ws.link_dofs[0].clone() {
                let jv = dvec3_at(jacobian, c * SPATIAL_DIM);
                let jw = dvec3_at(jacobian, c * SPATIAL_DIM + DIM);
                let qdot = f64::from(self.velocities[c]);
                if jw == DVec3::ZERO {
                    root_origin_velocity += jv * qdot;
                } else {
                    root_angvel += jw * qdot;
                }
            }
        }

        // Per DoF: its motion and the products every pair reads.
        for i in first_moving..nlinks {
            let link = &self.links[i];
            let jacobian = self.body_jacobians[i].as_slice();
            let r = ws.offsets[i];
            let composite = &ws.composites[i];
            // A planar joint below the root (patch 31, see the module documentation): a rotation
            // `c` has `(V_λ + U + V_L) × S_c`, `U` the velocity the joint's slides give. For one
            // DoF that is `2V_λ × S_c`, computed as before so that its bits stay.
            let several = i != 0 && ws.link_dofs[i].len() > 1;
            let mut joint_bias = Spatial::default();
            if several {
                let mut slides = DVec3::ZERO;
                for c in ws.link_dofs[i].clone() {
                    if dvec3_at(jacobian, c * SPATIAL_DIM + DIM) == DVec3::ZERO {
                        slides +=
                            dvec3_at(jacobian, c * SPATIAL_DIM) * f64::from(self.velocities[c]);
                    }
                }
                let parent_velocity = ws.velocities[link.parent_internal_id];
                joint_bias = parent_velocity
                    .add(Spatial::new(DVec3::ZERO, slides))
                    .add(ws.velocities[i]);
            }
            for c in ws.link_dofs[i].clone() {
                let jv = dvec3_at(jacobian, c * SPATIAL_DIM);
                let jw = dvec3_at(jacobian, c * SPATIAL_DIM + DIM);
                let motion = Spatial::new(jw, jv - jw.cross(r));
                ws.motions[c] = (motion, composite.inertia_times(motion));
                let coriolis_motion = if i == 0 {
                    // `V_root × S + ∂(0, v_o × ω)/∂q̇_c`.
                    let root_bias = if jw == DVec3::ZERO {
                        jv.cross(root_angvel)
                    } else {
                        root_origin_velocity.cross(jw)
                    };
                    let turned = ws.velocities[0].cross_motion(motion);
                    Spatial::new(turned.ang, turned.lin + root_bias)
                } else if several && jw != DVec3::ZERO {
                    joint_bias.cross_motion(motion)
                } else {
                    let parent_velocity = ws.velocities[link.parent_internal_id];
                    Spatial::new(parent_velocity.ang * 2.0, parent_velocity.lin * 2.0)
                        .cross_motion(motion)
                };
                let b_motion = composite.b_times(motion);
                let motion_momentum = motion.cross_force(composite.momentum);
                ws.dofs[c] = CompositeDof {
                    coriolis_motion,
                    velocity_force: composite
                        .inertia_times(coriolis_motion)
                        .add(b_motion)
                        .add(motion_momentum),
                    velocity_force_below: b_motion.sub(motion_momentum),
                };
            }
        }

        // Every pair of DoFs on one path from the root: `a` on link `k`, `c` on link `L`, `k`
        // an ancestor of `L` or `L` itself (and then `a ≤ c`), so `a ≤ c` always.
        let n = self.ndofs;
        let mass = self.augmented_mass.as_mut_slice();
        let acc = self.acc_augmented_mass.as_mut_slice();
        let dt = f64::from(dt);
        for i in first_moving..nlinks {
            for c in ws.link_dofs[i].clone() {
                let below_inertia_motion = ws.motions[c].1;
                let mut k = i;
                loop {
                    let upto = if k == i { c + 1 } else { ws.link_dofs[k].end };
                    for a in ws.link_dofs[k].start..upto {
                        let above_motion = ws.motions[a].0;
                        mass[a + c * n] = above_motion.dot(below_inertia_motion) as Real;
                        let (below, above) = (&ws.dofs[c], &ws.dofs[a]);
                        acc[a + c * n] = (dt * above_motion.dot(below.velocity_force)) as Real;
                        if a != c {
                            acc[c + a * n] = (dt
                                * (below_inertia_motion.dot(above.coriolis_motion)
                                    + below.velocity_force_below.dot(above_motion)))
                                as Real;
                        }
                    }
                    if k == 0 {
                        break;
                    }
                    k = ws.parents[k];
                }
            }
        }

        self.composite_workspace = ws;
    }

    /// `M` alone (no velocity terms), by the same arithmetic as [`Self::composite_mass_matrices`]
    /// with the velocity terms (the same bits), reading and writing only what `M` needs
    /// (gymfleet patch 35): the subtrees' inertias without momenta, no per-DoF velocity records,
    /// and two passes over the links instead of four. Forward, each link's own inertia at `p₀`
    /// and its DoFs' motions; backward (children first), each link's subtree is complete when
    /// it is reached, so it is added to its parent's and its DoFs' columns of `M` are written,
    /// in both triangles.
    fn composite_mass_matrix(&mut self, bodies: &RigidBodySet) {
        let nlinks = self.links.len();
        let n = self.ndofs;
        let mut ws = core::mem::take(&mut self.composite_workspace);
        ws.inertias.resize(nlinks, SubtreeInertia::default());
        ws.motions.resize(n, Default::default());
        ws.parents.clear();
        ws.link_dofs.clear();
        let com = |link: &super::MultibodyLink, rb: &RigidBody| {
            (link.local_to_world * rb.mprops.local_mprops.local_com).as_dvec3()
        };
        let root = &self.links[0];
        let p0 = com(root, &bodies[root.rigid_body]);
        // A fixed root is moved by no DoF: its DoFs (if any) have no motion, and no DoF reads its
        // subtree's inertia.
        let first_moving = if self.root_is_dynamic { 0 } else { 1 };
        for (i, link) in self.links.iter().enumerate() {
            let dofs = link.assembly_id..link.assembly_id + link.joint.ndofs();
            if i < first_moving {
                for c in dofs.clone() {
                    ws.motions[c].0 = Spatial::default();
                }
            } else {
                let rb = &bodies[link.rigid_body];
                let r = com(link, rb) - p0;
                ws.inertias[i] = SubtreeInertia::of_link(self.workspace.link_inertias[i], r);
                let jacobian = self.body_jacobians[i].as_slice();
                for c in dofs.clone() {
                    let jv = dvec3_at(jacobian, c * SPATIAL_DIM);
                    let jw = dvec3_at(jacobian, c * SPATIAL_DIM + DIM);
                    ws.motions[c].0 = Spatial::new(jw, jv - jw.cross(r));
                }
            }
            ws.parents.push(link.parent_internal_id);
            ws.link_dofs.push(dofs);
        }
        let mass = self.augmented_mass.as_mut_slice();
        for i in (first_moving..nlinks).rev() {
            let inertia = ws.inertias[i];
            let parent = ws.parents[i];
            if i != 0 && parent >= first_moving {
                ws.inertias[parent].accumulate(&inertia);
            }
            // Every pair of DoFs on one path from the root, `c` on this link: `a ≤ c` on it,
            // then every DoF of each ancestor.
            let own = ws.link_dofs[i].clone();
            for c in own.clone() {
                let below_inertia_motion = inertia.times(ws.motions[c].0);
                let mut write = |a: usize| {
                    let entry = ws.motions[a].0.dot(below_inertia_motion) as Real;
                    mass[a + c * n] = entry;
                    mass[c + a * n] = entry;
                };
                for a in own.start..=c {
                    write(a);
                }
                let mut k = i;
                while k != 0 {
                    k = ws.parents[k];
                    for a in ws.link_dofs[k].clone() {
                        write(a);
                    }
                }
            }
        }
        self.composite_workspace = ws;
    }
}
