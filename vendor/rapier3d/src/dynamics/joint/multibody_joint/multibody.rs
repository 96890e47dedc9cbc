use super::mass_matrix_lu::MassMatrixLu;
use super::multibody_link::{MultibodyLink, MultibodyLinkVec};
#[cfg(feature = "dim3")]
use super::multibody_workspace::MassColumn;
use super::multibody_workspace::MultibodyWorkspace;
use crate::alloc_prelude::*;
use crate::dynamics::integration_parameters::SpringCoefficients;
use crate::dynamics::solver::{GenericJointConstraint, WritebackId};
use crate::dynamics::{
    IntegrationParameters, RigidBodyHandle, RigidBodySet, RigidBodyType, RigidBodyVelocity,
};
#[cfg(feature = "dim2")]
use crate::math::SimdAngVector;
use crate::math::{
    ANG_DIM, AngDim, AngVector, DIM, DVector, Dim, Jacobian, Pose, Real, SPATIAL_DIM, Vector,
};
use crate::prelude::MultibodyJoint;
use crate::utils::{AngularInertiaOps, CrossProduct, CrossProductMatrix, IndexMut2, vect_to_na};
use na::{self, DMatrix, DVectorView, DVectorViewMut, Dyn, OMatrix, SMatrix, SVector, StorageMut};

#[cfg(doc)]
use crate::prelude::{GenericJoint, RigidBody};

#[cfg(feature = "dim3")]
#[path = "multibody_composite.rs"]
mod composite;
#[path = "multibody_buffers.rs"]
mod buffers;
#[cfg(all(test, feature = "dim3"))]
#[path = "multibody_lean_tests.rs"]
mod lean_tests;
#[cfg(all(test, feature = "dim3"))]
#[path = "multibody_mass_only_tests.rs"]
mod mass_only_tests;

#[repr(C)]
#[derive(Copy, Clone, Debug, Default)]
struct Force {
    linear: Vector,
    angular: AngVector,
}

impl Force {
    #[cfg(feature = "dim2")] // 3D projects link wrenches instead (gymfleet patch 33).
    fn new(linear: Vector, angular: AngVector) -> Self {
        Self { linear, angular }
    }

    fn as_vector(&self) -> &SVector<Real, SPATIAL_DIM> {
        unsafe { core::mem::transmute(self) }
    }
}

#[cfg(feature = "dim2")]
fn concat_rb_mass_matrix(mass: Vector, inertia: Real) -> SMatrix<Real, SPATIAL_DIM, SPATIAL_DIM> {
    let mut result = SMatrix::<Real, SPATIAL_DIM, SPATIAL_DIM>::zeros();
    result[(0, 0)] = mass.x;
    result[(1, 1)] = mass.y;
    result[(2, 2)] = inertia;
    result
}

/// The largest motion of any DoF (radians, or length units) within one substep below which a
/// multibody counts as still, and its mass matrix leaves out the velocity-dependent terms
/// (gymfleet patch, see `PATCHES.md`): those terms change the semi-implicit mass matrix by a
/// relative amount of the order of this motion, here 10⁻¹², some 10⁵ times below `f32`'s
/// resolution. A multibody held still in balance moves by about 10⁻¹⁶ per substep (rounding).
pub const NEGLIGIBLE_MOTION_PER_SUBSTEP: Real = 1.0e-12;

/// Makes `v` a zero vector of length `n`, reusing its allocation when it already has that
/// length (gymfleet patch: per-substep buffers live in the multibody's workspace).
fn resize_zeroed(v: &mut DVector, n: usize) {
    if v.len() == n {
        // On the contiguous storage: nalgebra's element-wise `fill` costs about a hundred
        // instructions for a vector of six (gymfleet patch 33).
        v.as_mut_slice().fill(0.0);
    } else {
        *v = DVector::zeros(n);
    }
}

/// The free axes of `joint`, in axis order, each with its DoF's index (the first is
/// `first_dof`): the set bits of its free-axis mask rather than all six axes (gymfleet patch 35).
fn free_axes(joint: &MultibodyJoint, first_dof: usize) -> impl Iterator<Item = (usize, usize)> {
    let mut free = !u32::from(joint.data.locked_axes.bits()) & ((1 << SPATIAL_DIM) - 1);
    let mut dof = first_dof;
    core::iter::from_fn(move || {
        if free == 0 {
            return None;
        }
        let axis = free.trailing_zeros() as usize;
        free &= free - 1;
        dof += 1;
        Some((axis, dof - 1))
    })
}

/// The three components at `slice[at..at + 3]` as a vector.
#[cfg(feature = "dim3")]
#[inline]
fn vec3_at(slice: &[Real], at: usize) -> Vector {
    Vector::new(slice[at], slice[at + 1], slice[at + 2])
}

#[cfg(feature = "dim3")]
#[inline]
fn set_vec3_at(slice: &mut [Real], at: usize, v: Vector) {
    slice[at] = v.x;
    slice[at + 1] = v.y;
    slice[at + 2] = v.z;
}

/// The root link's shift from its joint's child frame to its centre of mass, in world
/// coordinates (gymfleet patch, see `PATCHES.md`). Upstream leaves it zero, which is right
/// for a fixed root (it has no DoF) but makes a free root's jacobian map its linear DoFs
/// (the velocity of the body frame's origin, as [`MultibodyJoint::integrate`] treats them)
/// onto its centre of mass: a free base whose centre of mass is off its origin then turned
/// about the origin while the dynamics turned it about the centre of mass, and its centre
/// of mass drifted under internal torques alone.
fn root_shift23(link: &MultibodyLink, bodies: &RigidBodySet) -> Vector {
    let Some(rb) = bodies.get(link.rigid_body) else {
        return Vector::ZERO;
    };
    let c2 = link.local_to_world * Vector::from(link.joint.data.local_frame2.translation);
    let c3 = link.local_to_world * rb.mprops.local_mprops.local_com;
    c3 - c2
}

/// `J[lin, c] += J[ang, c] × shift` for the columns `c` in `columns` of a body jacobian `J`
/// (what `Jv += [shift×]ᵀ·Jw` computes, column by column).
#[cfg(feature = "dim3")]
fn add_angular_cross_to_linear(
    jacobian: &mut Jacobian<Real>,
    columns: core::ops::Range<usize>,
    shift: Vector,
) {
    let cols = jacobian.as_mut_slice();
    let entries = columns.start * SPATIAL_DIM..columns.end * SPATIAL_DIM;
    for col in cols[entries].chunks_exact_mut(SPATIAL_DIM) {
        let w = Vector::new(col[3], col[4], col[5]);
        let d = w.cross(shift);
        col[0] += d.x;
        col[1] += d.y;
        col[2] += d.z;
    }
}

#[cfg(feature = "dim2")]
fn add_angular_cross_to_linear(
    jacobian: &mut Jacobian<Real>,
    columns: core::ops::Range<usize>,
    shift: Vector,
) {
    let (mut j_v, j_w) = jacobian.rows_range_pair_mut(0..DIM, DIM..DIM + ANG_DIM);
    let shift_tr = vect_to_na(shift).gcross_matrix_tr();
    j_v.columns_range_mut(columns.clone())
        .gemm(1.0, &shift_tr, &j_w.columns_range(columns), 1.0);
}

/// A holonomic coupling between two generalized coordinates of a single
/// [`Multibody`], `q2 = coeff · q1 + offset`, enforced as a velocity-level
/// equality constraint. This is how MuJoCo's `<equality><joint>` (a polynomial
/// joint-to-joint coupling) is represented for the linear (first-order) case —
/// e.g. the robotiq gripper's two driver joints moving together.
#[cfg_attr(feature = "serde-serialize", derive(Serialize, Deserialize))]
#[derive(Copy, Clone, Debug)]
pub struct MultibodyDofCoupling {
    /// Internal id of the link owning the first joint.
    pub link1: usize,
    /// Local free-DoF index of the coupled DoF within `link1` (its position in
    /// that link's slice of the generalized vectors).
    pub dof1: usize,
    /// Spatial-coordinate axis (`0..6`) of `link1`'s coupled DoF, used to read
    /// its generalized position from the joint coords.
    pub axis1: usize,
    /// Internal id of the link owning the second joint.
    pub link2: usize,
    /// Local free-DoF index of the coupled DoF within `link2`.
    pub dof2: usize,
    /// Spatial-coordinate axis (`0..6`) of `link2`'s coupled DoF.
    pub axis2: usize,
    /// Linear coupling coefficient: the constraint is `q2 − coeff·q1 − offset = 0`.
    pub coeff: Real,
    /// Constant offset of the coupling.
    pub offset: Real,
}

/// A hard limit on a linear combination of one-coordinate DoFs (gymfleet patch 20, see
/// `PATCHES.md`): `min ≤ Σ coefᵢ·qᵢ ≤ max`, MuJoCo's range of a fixed tendon.
#[cfg_attr(feature = "serde-serialize", derive(Serialize, Deserialize))]
#[derive(Clone, Debug, PartialEq)]
pub struct MultibodyLinearLimit {
    /// The DoFs: (internal link id, local free-DoF index in that link, coefficient).
    pub dofs: Vec<(usize, usize, Real)>,
    /// The lower bound of the combination.
    pub min: Real,
    /// The upper bound.
    pub max: Real,
}

/// A rope (gymfleet patch 42, see `PATCHES.md`): the length of the straight path through
/// its points is at most `max`, MuJoCo's range of a spatial tendon.
#[cfg_attr(feature = "serde-serialize", derive(Serialize, Deserialize))]
#[derive(Clone, Debug, PartialEq)]
pub struct MultibodyPathLimit {
    /// The path's points, in order: `(Some(internal link id), point in the link's frame)`,
    /// or `(None, world point)` for a point that does not move.
    pub points: Vec<(Option<usize>, Vector)>,
    /// The longest the path may be.
    pub max: Real,
}

/// An articulated body simulated using the reduced-coordinates approach.
#[cfg_attr(feature = "serde-serialize", derive(Serialize, Deserialize))]
#[derive(Clone, Debug)]
pub struct Multibody {
    // TODO: serialization: skip the workspace fields.
    pub(crate) links: MultibodyLinkVec,
    pub(crate) velocities: DVector,
    pub(crate) damping: DVector,
    /// Per-DoF reflected rotor inertia (matches MuJoCo’s concept of `armature`).
    pub(crate) armature: DVector,
    /// Per-DoF dry joint friction (matches MuJoCo’s `frictionloss`).
    pub(crate) frictions: DVector,
    /// Per-DoF applied generalized forces (matches MuJoCo’s `qfrc_applied`): joint-space
    /// efforts (N·m on angular DoFs, N on linear DoFs) added to the dynamics at every
    /// substep until changed.
    pub(crate) applied_forces: DVector,
    pub(crate) accelerations: DVector,

    body_jacobians: Vec<Jacobian<Real>>,
    /// Whether the body jacobians hold only each link's own columns, the solver's update
    /// between two substeps (gymfleet patch 33, see
    /// [`Multibody::forward_kinematics_between_substeps`]).
    #[cfg_attr(feature = "serde-serialize", serde(skip))]
    body_jacobians_partial: bool,
    // NOTE: the mass matrices are dimensioned based on the non-kinematic degrees of
    //       freedoms only. The `Self::augmented_mass_permutation` sequence can be used to
    //       move dofs from/to a format that matches the augmented mass.
    // TODO: use sparse matrices?
    augmented_mass: DMatrix<Real>,
    inv_augmented_mass: MassMatrixLu,
    /// Whether `augmented_mass` changed since `inv_augmented_mass` was factorized (gymfleet
    /// patch, see `PATCHES.md`: it is factorized only when a constraint or the hard limits need
    /// it, see [`Multibody::factorize_inv_augmented_mass`]).
    inv_augmented_mass_stale: bool,
    /// Whether the links' poses, shifts and body jacobians, and the link bodies' poses, are
    /// those of the current coordinates, as the solver left them after the last substep of a
    /// step (gymfleet patch, see `PATCHES.md`); any mutable access to the links clears it.
    kinematics_current: bool,
    // The indexing sequence for moving all kinematics degrees of
    // freedoms to the end of the generalized coordinates vector.
    augmented_mass_indices: IndexSequence,

    acc_augmented_mass: DMatrix<Real>,
    acc_inv_augmented_mass: MassMatrixLu,
    /// Whether the last mass-matrix update left out the velocity terms because they were
    /// negligible, so that `acc_augmented_mass` is `augmented_mass` (gymfleet patch, see
    /// `PATCHES.md` and [`NEGLIGIBLE_MOTION_PER_SUBSTEP`]).
    velocity_terms_skipped: bool,

    ndofs: usize,
    pub(crate) root_is_dynamic: bool,
    pub(crate) solver_id: u32,
    self_contacts_enabled: bool,
    /// Whether joint limits are hard stops: see [`Multibody::set_hard_limits`].
    hard_limits: bool,
    /// Whether the velocity terms are explicit (gymfleet patch 26): see
    /// [`Multibody::set_explicit_velocity_terms`].
    #[cfg_attr(feature = "serde-serialize", serde(default))]
    explicit_velocity_terms: bool,
    /// Whether the joint springs are explicit forces of the substep's start (gymfleet patch
    /// 45): see [`Multibody::set_explicit_springs`].
    #[cfg_attr(feature = "serde-serialize", serde(default))]
    explicit_springs: bool,
    /// Whether the constraints see the mass matrix without the joints' damping, which then
    /// acts on their impulses and the step's forces together (gymfleet patch 50): see
    /// [`Multibody::set_damping_after_constraints`].
    #[cfg_attr(feature = "serde-serialize", serde(default))]
    damping_after_constraints: bool,
    /// Patch 50 in force for the dynamics last updated (the solver's substep is the whole
    /// pipeline step, and no DoF is kinematic), with their step `dt`.
    #[cfg_attr(feature = "serde-serialize", serde(skip))]
    damping_after_active: Option<Real>,
    /// Patch 50: the velocities at the substep's start, and `M + dt·D` factorized.
    #[cfg_attr(feature = "serde-serialize", serde(skip))]
    damping_start_velocities: DVector,
    #[cfg_attr(feature = "serde-serialize", serde(skip))]
    damped_mass: DMatrix<Real>,
    #[cfg_attr(feature = "serde-serialize", serde(skip))]
    inv_damped_mass: MassMatrixLu,
    /// Patch 50: the velocity change's workspace.
    #[cfg_attr(feature = "serde-serialize", serde(skip))]
    damping_workspace: DVector,
    /// The generalized impulses the hard limits applied to each DoF since the last
    /// [`Multibody::clear_hard_limit_impulses`] (gymfleet patch 17, see `PATCHES.md`); empty
    /// until a limit first stops a DoF, zeroed when the DoF count changes.
    hard_limit_impulses: DVector,

    /// Holonomic couplings between two of this multibody's generalized
    /// coordinates (`q2 = coeff·q1 + offset`), e.g. MuJoCo's
    /// `<equality><joint>`. Resolved as velocity constraints each step.
    couplings: Vec<MultibodyDofCoupling>,
    /// Hard limits on linear combinations of DoFs (gymfleet patch 20), enforced with the
    /// hard limits; cleared when the multibody is split.
    linear_limits: Vec<MultibodyLinearLimit>,
    /// Ropes (gymfleet patch 42), enforced after the linear limits; cleared when the
    /// multibody is split.
    path_limits: Vec<MultibodyPathLimit>,

    /*
     * Workspaces.
     */
    workspace: MultibodyWorkspace,
    /// Buffers of the composite-rigid-body construction of the mass matrices (gymfleet patch,
    /// see `PATCHES.md`).
    #[cfg(feature = "dim3")]
    #[cfg_attr(feature = "serde-serialize", serde(skip))]
    composite_workspace: composite::CompositeWorkspace,
    coriolis_v: Vec<OMatrix<Real, Dim, Dyn>>,
    coriolis_w: Vec<OMatrix<Real, AngDim, Dyn>>,
    i_coriolis_dt: Jacobian<Real>,
}
impl Default for Multibody {
    fn default() -> Self {
        Multibody::new()
    }
}

impl Multibody {
    /// Creates a new multibody with no link.
    pub fn new() -> Self {
        Self::with_self_contacts(true)
    }

    pub(crate) fn with_self_contacts(self_contacts_enabled: bool) -> Self {
        Multibody {
            links: MultibodyLinkVec(Vec::new()),
            velocities: DVector::zeros(0),
            damping: DVector::zeros(0),
            armature: DVector::zeros(0),
            frictions: DVector::zeros(0),
            applied_forces: DVector::zeros(0),
            accelerations: DVector::zeros(0),
            hard_limit_impulses: DVector::zeros(0),
            body_jacobians: Vec::new(),
            body_jacobians_partial: false,
            augmented_mass: DMatrix::zeros(0, 0),
            inv_augmented_mass: MassMatrixLu::default(),
            inv_augmented_mass_stale: false,
            kinematics_current: false,
            acc_augmented_mass: DMatrix::zeros(0, 0),
            acc_inv_augmented_mass: MassMatrixLu::default(),
            velocity_terms_skipped: false,
            augmented_mass_indices: IndexSequence::new(),
            ndofs: 0,
            solver_id: 0,
            workspace: MultibodyWorkspace::new(),
            #[cfg(feature = "dim3")]
            composite_workspace: Default::default(),
            coriolis_v: Vec::new(),
            coriolis_w: Vec::new(),
            i_coriolis_dt: Jacobian::zeros(0),
            root_is_dynamic: false,
            self_contacts_enabled,
            hard_limits: false,
            explicit_velocity_terms: false,
            explicit_springs: false,
            damping_after_constraints: false,
            damping_after_active: None,
            damping_start_velocities: DVector::zeros(0),
            damped_mass: DMatrix::zeros(0, 0),
            inv_damped_mass: MassMatrixLu::default(),
            damping_workspace: DVector::zeros(0),
            couplings: Vec::new(),
            linear_limits: Vec::new(),
            path_limits: Vec::new(),
            // solver_workspace: Some(SolverWorkspace::new()),
        }
    }

    pub(crate) fn with_root(handle: RigidBodyHandle, self_contacts_enabled: bool) -> Self {
        let mut mb = Multibody::with_self_contacts(self_contacts_enabled);
        // NOTE: we have no way of knowing if the root in fixed at this point, so
        //       we mark it as dynamic and will fix later with `Self::update_root_type`.
        mb.root_is_dynamic = true;
        let joint = MultibodyJoint::free(Pose::IDENTITY);
        mb.add_link(None, joint, handle);
        mb
    }

    pub(crate) fn remove_link(self, to_remove: usize, joint_only: bool) -> Vec<Multibody> {
        let mut result = vec![];
        let mut link2mb = vec![usize::MAX; self.links.len()];
        let mut link_id2new_id = vec![usize::MAX; self.links.len()];
        // Links whose joint is replaced by a fixed one: their DoFs no longer exist.
        let mut joint_replaced = vec![false; self.links.len()];

        // Split multibody and update the set of links and ndofs.
        for (i, mut link) in self.links.0.into_iter().enumerate() {
            let is_new_root = i == 0
                || !joint_only && link.parent_internal_id == to_remove
                || joint_only && i == to_remove;

            if !joint_only && i == to_remove {
                continue;
            } else if is_new_root {
                link2mb[i] = result.len();
                let mut mb = Multibody::with_self_contacts(self.self_contacts_enabled);
                mb.hard_limits = self.hard_limits;
                mb.explicit_velocity_terms = self.explicit_velocity_terms;
                mb.explicit_springs = self.explicit_springs;
                mb.damping_after_constraints = self.damping_after_constraints;

                result.push(mb);
            } else {
                link2mb[i] = link2mb[link.parent_internal_id]
            }

            let curr_mb = &mut result[link2mb[i]];
            link_id2new_id[i] = curr_mb.links.len();

            if is_new_root {
                let joint = MultibodyJoint::fixed(*link.local_to_world());
                link.joint = joint;
                joint_replaced[i] = true;
            }

            curr_mb.ndofs += link.joint().ndofs();
            curr_mb.links.push(link);
        }

        // Adjust all the internal ids, and copy the data from the
        // previous multibody to the new one.
        for mb in &mut result {
            mb.grow_buffers(mb.ndofs, mb.links.len());
            mb.workspace.resize(mb.links.len(), mb.ndofs);

            let mut assembly_id = 0;
            for (i, link) in mb.links.iter_mut().enumerate() {
                let link_ndofs = link.joint().ndofs();
                mb.velocities
                    .rows_mut(assembly_id, link_ndofs)
                    .copy_from(&self.velocities.rows(link.assembly_id, link_ndofs));
                mb.damping
                    .rows_mut(assembly_id, link_ndofs)
                    .copy_from(&self.damping.rows(link.assembly_id, link_ndofs));
                mb.armature
                    .rows_mut(assembly_id, link_ndofs)
                    .copy_from(&self.armature.rows(link.assembly_id, link_ndofs));
                mb.frictions
                    .rows_mut(assembly_id, link_ndofs)
                    .copy_from(&self.frictions.rows(link.assembly_id, link_ndofs));
                mb.applied_forces
                    .rows_mut(assembly_id, link_ndofs)
                    .copy_from(&self.applied_forces.rows(link.assembly_id, link_ndofs));
                mb.accelerations
                    .rows_mut(assembly_id, link_ndofs)
                    .copy_from(&self.accelerations.rows(link.assembly_id, link_ndofs));

                link.internal_id = i;
                link.assembly_id = assembly_id;

                // NOTE: for the root, the current`link.parent_internal_id` is invalid since that
                //       parent lies in a different multibody now.
                link.parent_internal_id = if i != 0 {
                    link_id2new_id[link.parent_internal_id]
                } else {
                    0
                };
                assembly_id += link_ndofs;
            }
        }

        // Keep the couplings whose DoFs still exist and ended up in the same multibody.
        for coupling in &self.couplings {
            let (l1, l2) = (coupling.link1, coupling.link2);
            let kept = |l: usize| link_id2new_id[l] != usize::MAX && !joint_replaced[l];
            if kept(l1) && kept(l2) && link2mb[l1] == link2mb[l2] {
                result[link2mb[l1]].couplings.push(MultibodyDofCoupling {
                    link1: link_id2new_id[l1],
                    link2: link_id2new_id[l2],
                    ..*coupling
                });
            }
        }

        result
    }

    pub(crate) fn append(&mut self, mut rhs: Multibody, parent: usize, joint: MultibodyJoint) {
        self.kinematics_current = false;
        let joint_ndofs = joint.ndofs();
        let rhs_root_ndofs = rhs.links[0].joint.ndofs();
        let ndofs_before_append = self.velocities.len();
        let base_internal_id = self.links.len();
        // Values for rhs will be copied into the buffers of `self` starting at this index.
        let rhs_copy_shift = ndofs_before_append + joint_ndofs;
        // Number of dofs to copy from rhs. The root’s dofs isn’t included because it will be
        // replaced by `joint`.
        let rhs_copy_ndofs = rhs.ndofs - rhs_root_ndofs;

        // Adjust the ids of all the rhs links except the first one.
        for link in &mut rhs.links.0[1..] {
            link.assembly_id =
                (link.assembly_id + ndofs_before_append + joint_ndofs) - rhs_root_ndofs;
            link.internal_id += base_internal_id;
            link.parent_internal_id += base_internal_id;
        }

        // Adjust the first link.
        {
            rhs.links[0].joint = joint;
            rhs.links[0].assembly_id = ndofs_before_append;
            rhs.links[0].internal_id = base_internal_id;
            rhs.links[0].parent_internal_id = parent;
        }

        // Grow buffers then append data from rhs.
        self.grow_buffers(rhs_copy_ndofs + joint_ndofs, rhs.links.len());

        if rhs_copy_ndofs > 0 {
            self.velocities
                .rows_mut(rhs_copy_shift, rhs_copy_ndofs)
                .copy_from(&rhs.velocities.rows(rhs_root_ndofs, rhs_copy_ndofs));
            self.damping
                .rows_mut(rhs_copy_shift, rhs_copy_ndofs)
                .copy_from(&rhs.damping.rows(rhs_root_ndofs, rhs_copy_ndofs));
            self.armature
                .rows_mut(rhs_copy_shift, rhs_copy_ndofs)
                .copy_from(&rhs.armature.rows(rhs_root_ndofs, rhs_copy_ndofs));
            self.frictions
                .rows_mut(rhs_copy_shift, rhs_copy_ndofs)
                .copy_from(&rhs.frictions.rows(rhs_root_ndofs, rhs_copy_ndofs));
            self.applied_forces
                .rows_mut(rhs_copy_shift, rhs_copy_ndofs)
                .copy_from(&rhs.applied_forces.rows(rhs_root_ndofs, rhs_copy_ndofs));
            self.accelerations
                .rows_mut(rhs_copy_shift, rhs_copy_ndofs)
                .copy_from(&rhs.accelerations.rows(rhs_root_ndofs, rhs_copy_ndofs));
        }

        // Set the default damping for the new joint.
        rhs.links[0]
            .joint
            .default_damping(&mut self.damping.rows_mut(ndofs_before_append, joint_ndofs));

        self.links.append(&mut rhs.links);
        self.ndofs = self.velocities.len();
        self.workspace.resize(self.links.len(), self.ndofs);

        // gymfleet patch 20: the rhs linear limits follow its links, but those on its root.
        self.linear_limits.extend(
            rhs.linear_limits
                .iter()
                .filter(|l| l.dofs.iter().all(|&(link, _, _)| link != 0))
                .map(|l| MultibodyLinearLimit {
                    dofs: l.dofs.iter().map(|&(link, k, c)| (link + base_internal_id, k, c)).collect(),
                    ..l.clone()
                }),
        );
        // gymfleet patch 42: so do its ropes, but those through its root.
        self.path_limits.extend(
            rhs.path_limits
                .iter()
                .filter(|l| l.points.iter().all(|&(link, _)| link != Some(0)))
                .map(|l| MultibodyPathLimit {
                    points: l
                        .points
                        .iter()
                        .map(|&(link, p)| (link.map(|id| id + base_internal_id), p))
                        .collect(),
                    ..l.clone()
                }),
        );
        // The rhs couplings follow its links, except the ones on its root whose joint was replaced.
        self.couplings.extend(
            rhs.couplings
                .iter()
                .filter(|c| c.link1 != 0 && c.link2 != 0)
                .map(|c| MultibodyDofCoupling {
                    link1: c.link1 + base_internal_id,
                    link2: c.link2 + base_internal_id,
                    ..*c
                }),
        );
        // Self-contacts stay disabled for the links of a multibody that had them disabled.
        self.self_contacts_enabled &= rhs.self_contacts_enabled;
        // Hard limits stay enabled for the links of a multibody that had them enabled.
        self.hard_limits |= rhs.hard_limits;
        // The velocity terms stay implicit unless both multibodies had them explicit.
        self.explicit_velocity_terms &= rhs.explicit_velocity_terms;
        // The springs stay implicit unless both multibodies had them explicit.
        self.explicit_springs &= rhs.explicit_springs;
        // The constraints see the damping unless both multibodies had it after them.
        self.damping_after_constraints &= rhs.damping_after_constraints;
    }

    /// Whether self-contacts are enabled on this multibody.
    ///
    /// If set to `false` no two link from this multibody can generate contacts, even
    /// if the contact is enabled on the individual joint with [`GenericJoint::contacts_enabled`].
    pub fn self_contacts_enabled(&self) -> bool {
        self.self_contacts_enabled
    }

    /// Sets whether self-contacts are enabled on this multibody.
    ///
    /// If set to `false` no two link from this multibody can generate contacts, even
    /// if the contact is enabled on the individual joint with [`GenericJoint::contacts_enabled`].
    pub fn set_self_contacts_enabled(&mut self, enabled: bool) {
        self.self_contacts_enabled = enabled;
    }

    /// The inverse augmented mass matrix of this multibody.
    ///
    /// The solver factorizes it only in the substeps where a constraint on this multibody (a
    /// contact, a joint, a motor, dry friction, a coupling, a limit it is past) or a hard limit
    /// needs it; call [`Multibody::factorize_inv_augmented_mass`] first to be sure it matches the
    /// last mass matrix.
    pub fn inv_augmented_mass(&self) -> &MassMatrixLu {
        debug_assert!(
            !self.inv_augmented_mass_stale,
            "inv_augmented_mass read before factorize_inv_augmented_mass"
        );
        &self.inv_augmented_mass
    }

    /// Factorizes the augmented mass matrix built by the last mass-matrix update into
    /// [`Multibody::inv_augmented_mass`], if it has not been already (gymfleet patch, see
    /// `PATCHES.md`).
    pub fn factorize_inv_augmented_mass(&mut self) {
        if self.inv_augmented_mass_stale {
            if self.velocity_terms_skipped {
                // Both matrices are the same: so are their factorizations.
                self.inv_augmented_mass
                    .copy_from(&self.acc_inv_augmented_mass);
            } else {
                let effective_dim = self
                    .augmented_mass_indices
                    .dim_after_removal(self.augmented_mass.nrows());
                // gymfleet patch 29: the plain matrix is symmetric positive definite.
                self.inv_augmented_mass
                    .factorize_symmetric_leading(&self.augmented_mass, effective_dim);
            }
            self.inv_augmented_mass_stale = false;
        }
    }

    /// Records that the solver just ran forward kinematics on the coordinates it integrated
    /// and wrote the link bodies' poses (gymfleet patch, see `PATCHES.md`).
    pub(crate) fn set_kinematics_current(&mut self, current: bool) {
        self.kinematics_current = current;
    }

    /// Whether the next step can skip its forward kinematics (gymfleet patch, see
    /// `PATCHES.md`): the solver left the kinematics current, nothing has touched the links
    /// since, the root is fixed (a kinematic root moves by its body's pose, a free root's pose
    /// is read back from its body) and no link body was modified by the user.
    pub(crate) fn kinematics_are_current(&self, bodies: &RigidBodySet) -> bool {
        self.kinematics_current
            && self.links.iter().all(|link| {
                bodies.get(link.rigid_body).is_some_and(|rb| {
                    rb.changes.is_empty() && (link.internal_id != 0 || rb.is_fixed())
                })
            })
    }

    /// The solver's per-substep update of the dynamics at the current configuration: the
    /// links' velocities, both mass matrices, and the free accelerations. The plain mass
    /// matrix is factorized only if the island's contacts or impulse joints
    /// (`external_constraints`) or this multibody's own constraints may read it (gymfleet
    /// patch, see `PATCHES.md`).
    pub(crate) fn update_dynamics(
        &mut self,
        dt: Real,
        bodies: &mut RigidBodySet,
        external_constraints: bool,
    ) {
        self.update_velocities(bodies);
        self.update_link_inertias(bodies);
        self.update_mass_matrix_with_link_inertias(dt, bodies);
        if external_constraints || self.own_constraints_need_inv_augmented_mass() {
            self.factorize_inv_augmented_mass();
        }
        self.update_acceleration_with_link_inertias(dt, bodies);
    }

    /// Each link's effective mass and world-space angular inertia at the current configuration,
    /// into `workspace.link_inertias` (gymfleet patch 35): the mass matrices and the
    /// accelerations of one substep read them, and inverting the world inverse inertia is
    /// the dearest part of both.
    fn update_link_inertias(&mut self, bodies: &RigidBodySet) {
        let inertias = &mut self.workspace.link_inertias;
        inertias.clear();
        inertias.extend(self.links.iter().map(|link| {
            let mprops = &bodies[link.rigid_body].mprops;
            (mprops.effective_mass(), mprops.effective_angular_inertia())
        }));
    }

    /// Whether this multibody's own velocity constraints need [`Multibody::inv_augmented_mass`]
    /// at its current configuration (gymfleet patch, see `PATCHES.md`): a motor, dry friction or
    /// a DoF coupling always does, a limit only while the joint is past it (the same test as
    /// the limit constraint's). Contacts and impulse joints are the solver's to add.
    pub(crate) fn own_constraints_need_inv_augmented_mass(&self) -> bool {
        !self.couplings.is_empty()
            || self.frictions.iter().any(|f| *f > 0.0)
            || self
                .links
                .iter()
                .any(|link| link.joint.has_engaged_velocity_constraints())
    }

    /// The first link of this multibody.
    #[inline]
    pub fn root(&self) -> &MultibodyLink {
        &self.links[0]
    }

    /// Mutable reference to the first link of this multibody.
    #[inline]
    pub fn root_mut(&mut self) -> &mut MultibodyLink {
        self.kinematics_current = false;
        &mut self.links[0]
    }

    /// Reference `i`-th multibody link of this multibody.
    ///
    /// Return `None` if there is less than `i + 1` multibody links.
    #[inline]
    pub fn link(&self, id: usize) -> Option<&MultibodyLink> {
        self.links.get(id)
    }

    /// Mutable reference to the multibody link with the given id.
    ///
    /// Return `None` if the given id does not identifies a multibody link part of `self`.
    #[inline]
    pub fn link_mut(&mut self, id: usize) -> Option<&mut MultibodyLink> {
        self.kinematics_current = false;
        self.links.get_mut(id)
    }

    /// The number of links on this multibody.
    pub fn num_links(&self) -> usize {
        self.links.len()
    }

    /// Iterator through all the links of this multibody.
    ///
    /// All link are guaranteed to be yielded before its descendant.
    pub fn links(&self) -> impl Iterator<Item = &MultibodyLink> {
        self.links.iter()
    }

    /// Mutable iterator through all the links of this multibody.
    ///
    /// All link are guaranteed to be yielded before its descendant.
    pub fn links_mut(&mut self) -> impl Iterator<Item = &mut MultibodyLink> {
        self.kinematics_current = false;
        self.links.iter_mut()
    }

    /// The vector of damping applied to this multibody.
    #[inline]
    pub fn damping(&self) -> &DVector {
        &self.damping
    }

    /// Mutable vector of damping applied to this multibody.
    #[inline]
    pub fn damping_mut(&mut self) -> &mut DVector {
        &mut self.damping
    }

    /// The vector of per-DoF armature (reflected rotor inertia) of this multibody: additional
    /// inertia added directly to the mass matrix, simulating the joint's own weight distribution.
    #[inline]
    pub fn armature(&self) -> &DVector {
        &self.armature
    }

    /// Mutable vector of per-DoF armature (reflected rotor inertia) of this
    /// multibody.
    #[inline]
    pub fn armature_mut(&mut self) -> &mut DVector {
        &mut self.armature
    }

    /// The vector of per-DoF dry joint friction (MuJoCo's `frictionloss`, in N
    /// or N·m): the largest force friction may generate on that DoF.
    #[inline]
    pub fn frictions(&self) -> &DVector {
        &self.frictions
    }

    /// Mutable vector of per-DoF dry joint friction of this multibody.
    #[inline]
    pub fn frictions_mut(&mut self) -> &mut DVector {
        &mut self.frictions
    }

    /// The per-DoF applied generalized forces of this multibody (MuJoCo's `qfrc_applied`):
    /// an effort on each degree of freedom, in N·m for angular DoFs and N for linear ones.
    ///
    /// A joint-space effort is what a motor at the joint exerts: equal and opposite on the
    /// joint's two links, always along the joint's current axis. It is part of the dynamics of
    /// every substep (unlike a force on a rigid-body, whose direction is fixed in world space
    /// for the whole step), and it persists until changed.
    #[inline]
    pub fn applied_forces(&self) -> &DVector {
        &self.applied_forces
    }

    /// Mutable per-DoF applied generalized forces of this multibody; see
    /// [`Multibody::applied_forces`].
    #[inline]
    pub fn applied_forces_mut(&mut self) -> &mut DVector {
        &mut self.applied_forces
    }

    /// Whether this multibody's joint limits are hard stops; see [`Multibody::set_hard_limits`].
    #[inline]
    pub fn hard_limits(&self) -> bool {
        self.hard_limits
    }

    /// Makes this multibody's joint limits hard stops (default: `false`).
    ///
    /// The limit constraint of a multibody joint only engages once the joint is already past
    /// its limit, so a joint driven hard can go past it by `velocity × dt` within one substep
    /// (tens of degrees for a light link under a large effort) before it is pushed back. With
    /// hard limits, after every substep's position integration each limited DoF found past a
    /// limit is put back exactly on it, and its outward velocity is removed by an inelastic
    /// generalized impulse through the mass matrix (which moves the coupled DoFs as the impact
    /// would).
    #[inline]
    pub fn set_hard_limits(&mut self, enabled: bool) {
        self.hard_limits = enabled;
    }

    /// Whether the coriolis, centrifugal and gyroscopic forces enter each substep explicitly;
    /// see [`Multibody::set_explicit_velocity_terms`] (gymfleet patch 26).
    #[inline]
    pub fn explicit_velocity_terms(&self) -> bool {
        self.explicit_velocity_terms
    }

    /// Applies the velocity-dependent forces (coriolis, centrifugal, gyroscopic) explicitly, as
    /// forces of the substep's start, instead of linearizing them into the substep's mass
    /// matrix (default: `false`, the semi-implicit form; gymfleet patch 26, see `PATCHES.md`).
    ///
    /// This is MuJoCo's `Euler` integrator: joint damping and springs stay implicit, the
    /// velocity terms do not. It saves building their derivative and a second factorization
    /// every substep, but a free chain without damping can gain energy and diverge where the
    /// semi-implicit form (MuJoCo's `implicit`) stays finite: use it where the model was made
    /// for MuJoCo's `Euler`.
    #[inline]
    pub fn set_explicit_velocity_terms(&mut self, explicit: bool) {
        self.explicit_velocity_terms = explicit;
    }

    /// gymfleet patch 45: with `explicit`, each joint spring is the force `−k·(q − rest)` of
    /// the substep's start, as MuJoCo's Euler integrator has it (implicit in damping only),
    /// instead of a backward-Euler spring (`dt²·k` on the mass matrix's diagonal and `−k·dt·v`
    /// in the force). The implicit spring is the default: it keeps a stiff spring on a light
    /// link stable where the explicit one may not be, as in MuJoCo.
    pub fn set_explicit_springs(&mut self, explicit: bool) {
        self.explicit_springs = explicit;
        self.kinematics_current = false;
    }

    /// gymfleet patch 50: with `after`, the constraints (contacts, limits, loops) are solved
    /// on the mass matrix without the joints' damping `D`, and the substep's change of
    /// velocity is then taken through `M + dt·D`: `v⁺ = v₀ + (M + dt·D)⁻¹·M·(v − v₀)`, `v` the
    /// solver's velocities. That is MuJoCo's order (`mj_fwdConstraint` on `qM`, then
    /// `mj_EulerSkip`'s `qacc = (M + h·D)⁻¹·(qfrc_smooth + qfrc_constraint)`), where Rapier's
    /// rows see `M + dt·D` itself, so that a damped joint's contact pushes less than
    /// MuJoCo's. Free motion is the same either way. It applies where a pipeline step is one
    /// solver substep and no DoF is kinematic; elsewhere the damping stays in the matrix.
    pub fn set_damping_after_constraints(&mut self, after: bool) {
        self.damping_after_constraints = after;
    }

    /// Whether patch 50 is on: see [`Multibody::set_damping_after_constraints`].
    pub fn damping_after_constraints(&self) -> bool {
        self.damping_after_constraints
    }

    /// gymfleet patch 50: arms (or disarms) the damping order for the dynamics the solver is
    /// about to update, at step `dt` (`None`: damping in the matrix, Rapier's order).
    pub(crate) fn arm_damping_after_constraints(&mut self, dt: Option<Real>) {
        self.damping_after_active = dt.filter(|_| self.damping_after_constraints);
    }

    /// gymfleet patch 50: the multibody's velocities `v` (the solver's, just copied in)
    /// become `v₀ + (M + dt·D)⁻¹·M·(v − v₀)` when the damping order is in force for the
    /// dynamics last updated; they are left as they are otherwise.
    pub(crate) fn damp_after_constraints(&mut self) {
        if self.damping_after_active.is_none() || !self.inv_damped_mass.is_invertible() {
            return;
        }
        let n = self.ndofs;
        if self.damping_workspace.len() != n {
            self.damping_workspace = DVector::zeros(n);
        }
        let x = self.damping_workspace.as_mut_slice();
        x.fill(0.0);
        let mass = self.augmented_mass.as_slice();
        let (v, v0) = (self.velocities.as_slice(), self.damping_start_velocities.as_slice());
        for c in 0..n {
            let d = v[c] - v0[c];
            if d != 0.0 {
                for (xr, m) in x.iter_mut().zip(&mass[c * n..(c + 1) * n]) {
                    *xr += m * d;
                }
            }
        }
        if self.inv_damped_mass.solve_mut(&mut self.damping_workspace) {
            let v = self.velocities.as_mut_slice();
            for ((vi, v0i), xi) in v.iter_mut().zip(v0).zip(self.damping_workspace.iter()) {
                *vi = v0i + xi;
            }
        }
    }

    /// gymfleet patch 50: ends the damping order for this step (the solver's velocities
    /// were overwritten with ones it already applied to).
    pub(crate) fn disarm_damping_after_constraints(&mut self) {
        self.damping_after_active = None;
    }

    /// Hard limits on linear combinations of one-coordinate DoFs (gymfleet patch 20):
    /// enforced, when [`Multibody::hard_limits`] is on, after the per-DoF stops of every
    /// substep: a combination found past a bound is put back on it by moving its own DoFs
    /// along its coefficients, and its outward rate is removed by an inelastic generalized
    /// impulse `Δv = M⁻¹·Jᵀ·λ`, `λ = −J·v / (J·M⁻¹·Jᵀ)`. Set them once the tree is complete;
    /// splitting the multibody clears them. A limit with `min == max` is an equality (gymfleet
    /// patch 42): its combination is put back on the value and its whole rate removed after
    /// every substep, which side it drifted to.
    pub fn set_linear_limits(&mut self, limits: Vec<MultibodyLinearLimit>) {
        self.linear_limits = limits;
    }

    /// Ropes (gymfleet patch 42): enforced, when [`Multibody::hard_limits`] is on, after the
    /// linear limits of every substep: a path found longer than its `max` is shortened to it by
    /// the least-action displacement `Δq = M⁻¹·Jᵀ·λ` (`J` the path length's jacobian, one
    /// Newton step on the length), and its lengthening rate is removed by the inelastic
    /// impulse `Δv = M⁻¹·Jᵀ·λ`, `λ = −J·v / (J·M⁻¹·Jᵀ)`. A slack rope does nothing. Set them
    /// once the tree is complete; splitting the multibody clears them.
    pub fn set_path_limits(&mut self, limits: Vec<MultibodyPathLimit>) {
        self.path_limits = limits;
    }

    pub(crate) fn add_link(
        &mut self,
        parent: Option<usize>, // TODO: should be a RigidBodyHandle?
        dof: MultibodyJoint,
        body: RigidBodyHandle,
    ) -> &mut MultibodyLink {
        self.kinematics_current = false;
        assert!(
            parent.is_none() || !self.links.is_empty(),
            "Multibody::build_body: invalid parent id."
        );

        /*
         * Compute the indices.
         */
        let assembly_id = self.velocities.len();
        let internal_id = self.links.len();

        /*
         * Grow the buffers.
         */
        let ndofs = dof.ndofs();
        self.grow_buffers(ndofs, 1);
        self.ndofs += ndofs;

        /*
         * Setup default damping.
         */
        dof.default_damping(&mut self.damping.rows_mut(assembly_id, ndofs));

        /*
         * Create the multibody.
         */
        let local_to_parent = dof.body_to_parent();
        let local_to_world;

        let parent_internal_id;
        if let Some(parent) = parent {
            parent_internal_id = parent;
            let parent_link = &mut self.links[parent_internal_id];
            local_to_world = parent_link.local_to_world * local_to_parent;
        } else {
            parent_internal_id = 0;
            local_to_world = local_to_parent;
        }

        let rb = MultibodyLink::new(
            body,
            internal_id,
            assembly_id,
            parent_internal_id,
            dof,
            local_to_world,
            local_to_parent,
        );

        self.links.push(rb);
        self.workspace.resize(self.links.len(), self.ndofs);

        &mut self.links[internal_id]
    }

    fn grow_buffers(&mut self, ndofs: usize, num_jacobians: usize) {
        let len = self.velocities.len();
        self.velocities.resize_vertically_mut(len + ndofs, 0.0);
        self.damping.resize_vertically_mut(len + ndofs, 0.0);
        self.armature.resize_vertically_mut(len + ndofs, 0.0);
        self.frictions.resize_vertically_mut(len + ndofs, 0.0);
        self.applied_forces.resize_vertically_mut(len + ndofs, 0.0);
        self.accelerations.resize_vertically_mut(len + ndofs, 0.0);
        self.body_jacobians
            .extend((0..num_jacobians).map(|_| Jacobian::zeros(0)));
    }

    #[cfg(test)]
    pub(crate) fn update_acceleration(&mut self, dt: Real, bodies: &RigidBodySet) {
        self.update_link_inertias(bodies);
        self.update_acceleration_with_link_inertias(dt, bodies);
    }

    /// [`Self::update_acceleration`] with `workspace.link_inertias` current.
    fn update_acceleration_with_link_inertias(&mut self, dt: Real, bodies: &RigidBodySet) {
        if self.ndofs == 0 {
            return; // Nothing to do.
        }

        // In 3D the backward pass writes every DoF (gymfleet patch 33).
        #[cfg(feature = "dim2")]
        self.accelerations.fill(0.0);

        // If there is significant movement, the semi-implicit coriolis term
        // occasionally cause instabilities due to the matrix being near singular.
        // To prevent that, we enable a check that verifies the result and fallbacks
        // to the explicit term if needed.
        // gymfleet patch 27 (see `PATCHES.md`): not when the mass matrix left the velocity
        // terms out (explicit velocity terms, or a still multibody). Both matrices are then
        // the same, so the fallback would solve the same system with the same factors and
        // get the same bits; only its last-chance clearing of non-finite results is kept.
        let significant_motion = dt * self.velocities.amax() >= 1.0e-3;
        let check_implicit_coriolis_divergence = significant_motion && !self.velocity_terms_skipped;
        // Generalized forces that derive from positions or external inputs
        // (gravity, user forces, spring position terms), kept in a reused buffer
        // (gymfleet patch, see `PATCHES.md`).
        let mut pos_forces = core::mem::take(&mut self.workspace.pos_forces);
        if check_implicit_coriolis_divergence {
            resize_zeroed(&mut pos_forces, self.ndofs);
        }

        #[cfg(feature = "dim3")]
        {
            let nlinks = self.links.len();
            self.workspace.wrenches.resize(nlinks, [Vector::ZERO; 2]);
            if check_implicit_coriolis_divergence {
                self.workspace
                    .applied_wrenches
                    .resize(nlinks, [Vector::ZERO; 2]);
            }
        }

        // Eqn 42 to 45
        for i in 0..self.links.len() {
            let link = &self.links[i];
            let rb = &bodies[link.rigid_body];

            let mut acc = RigidBodyVelocity::zero();

            if i != 0 {
                let parent_id = link.parent_internal_id;
                let parent_link = &self.links[parent_id];
                let parent_rb = &bodies[parent_link.rigid_body];

                acc += self.workspace.accs[parent_id];
                // The 2.0 originates from the two identical terms of Jdot (the terms become
                // identical once they are multiplied by the generalized velocities).
                acc.linvel += 2.0 * parent_rb.vels.angvel.gcross(link.joint_velocity.linvel);
                #[cfg(feature = "dim3")]
                {
                    acc.angvel += parent_rb.vels.angvel.cross(link.joint_velocity.angvel);
                }

                acc.linvel += parent_rb
                    .vels
                    .angvel
                    .gcross(parent_rb.vels.angvel.gcross(link.shift02));
                acc.linvel += self.workspace.accs[parent_id].angvel.gcross(link.shift02);
            }

            acc.linvel += rb.vels.angvel.gcross(rb.vels.angvel.gcross(link.shift23));
            acc.linvel += acc.angvel.gcross(link.shift23);

            self.workspace.accs[i] = acc;

            // TODO: should gyroscopic forces already be computed by the rigid-body itself
            //       (at the same time that we add the gravity force)?
            let gyroscopic;
            let (rb_mass, rb_inertia) = self.workspace.link_inertias[i];

            #[cfg(feature = "dim3")]
            {
                let angvel = rb.vels.angvel;
                let inertia_times_angvel = rb_inertia * angvel;
                gyroscopic = angvel.cross(inertia_times_angvel);
            }
            #[cfg(feature = "dim2")]
            {
                gyroscopic = 0.0;
            }

            let external_force = rb.forces.force - rb_mass * acc.linvel;
            let external_torque = rb.forces.torque - gyroscopic - rb_inertia * acc.angvel;
            // gymfleet patch 33 (see `PATCHES.md`): in 3D, `Jᵀ·f` is summed by the backward
            // pass below, which reads only each link's own columns of its body jacobian.
            #[cfg(feature = "dim3")]
            {
                self.workspace.wrenches[i] = [external_force, external_torque];
                if check_implicit_coriolis_divergence {
                    self.workspace.applied_wrenches[i] = [rb.forces.force, rb.forces.torque];
                }
            }
            #[cfg(feature = "dim2")]
            {
                // The body jacobian is zero past the link's span (see `update_body_jacobians`).
                let span = link.assembly_id + link.joint.ndofs();
                let body_jacobian = self.body_jacobians[i].columns(0, span);
                let external_forces = Force::new(external_force, external_torque);
                self.accelerations.rows_mut(0, span).gemv_tr(
                    1.0,
                    &body_jacobian,
                    external_forces.as_vector(),
                    1.0,
                );

                if check_implicit_coriolis_divergence {
                    let applied_forces = Force::new(rb.forces.force, rb.forces.torque);
                    pos_forces.rows_mut(0, span).gemv_tr(
                        1.0,
                        &body_jacobian,
                        applied_forces.as_vector(),
                        1.0,
                    );
                }
            }
        }
        #[cfg(feature = "dim3")]
        self.project_link_wrenches(check_implicit_coriolis_divergence, &mut pos_forces);

        // Joint-space efforts (see `Self::applied_forces`).
        self.accelerations += &self.applied_forces;
        if check_implicit_coriolis_divergence {
            pos_forces += &self.applied_forces;
        }

        self.accelerations
            .cmpy(-1.0, &self.damping, &self.velocities, 1.0);

        // Implicit joint springs: backward-Euler at `q⁺ = q + dt·v⁺` gives `-k·(q − rest) − k·dt·v⁺`,
        // with the `v⁺` part implicit via the `dt²·k` mass-matrix diagonal (see `update_mass_matrix`).
        // Consistency requires BOTH `-k·(q − rest)` and `-k·dt·v` here, else the spring is only semi-implicit.
        for link in self.links.iter() {
            let joint = &link.joint;
            for (a, idx) in free_axes(joint, link.assembly_id) {
                let k = joint.spring_stiffness[a];
                if k != 0.0 {
                    let q = joint.coords[a];
                    let rest = joint.spring_ref[a];
                    let spring_pos_force = -k * (q - rest);
                    // gymfleet patch 45: an explicit spring has no velocity part.
                    let implicit = if self.explicit_springs { 0.0 } else { k * dt };
                    self.accelerations[idx] += spring_pos_force - implicit * self.velocities[idx];
                    if check_implicit_coriolis_divergence {
                        pos_forces[idx] += spring_pos_force;
                    }
                }
            }
        }

        // Snapshot the full generalized forces: the energy guard may need them
        // for a re-solve with the plain mass matrix.
        let mut gen_forces = core::mem::take(&mut self.workspace.gen_forces);
        if check_implicit_coriolis_divergence {
            resize_zeroed(&mut gen_forces, self.ndofs);
            gen_forces.copy_from(&self.accelerations);
        }

        self.augmented_mass_indices
            .with_rearranged_rows_mut(&mut self.accelerations, |accs| {
                self.acc_inv_augmented_mass.solve_mut(accs);
            });

        if check_implicit_coriolis_divergence {
            self.free_velocity_energy_guard(dt, &gen_forces, &pos_forces);
        } else if significant_motion && !self.accelerations.iter().all(|x| x.is_finite()) {
            // The energy guard's last chance, which its fallback would reach with these same
            // values (patch 27).
            self.accelerations.fill(0.0);
        }
        self.workspace.pos_forces = pos_forces;
        self.workspace.gen_forces = gen_forces;
    }

    /// `Jᵀ·f` over the links (gymfleet patch 33, see `PATCHES.md`): `accelerations` (and, if
    /// `applied`, `pos_forces`) get, for each DoF, the dot product of its column of its own
    /// link's body jacobian with the wrench at that link's centre of mass of all the forces on
    /// the link's subtree (`workspace.wrenches`, and `workspace.applied_wrenches`). A column
    /// of an ancestor's DoF in a descendant's body jacobian is the ancestor's own column
    /// shifted to the descendant's centre of mass, so moving each wrench to its parent's
    /// centre of mass (children come after their parents) gives the same sums as the
    /// per-link `J·ᵀf`, without the ancestors' columns.
    #[cfg(feature = "dim3")]
    fn project_link_wrenches(&mut self, applied: bool, pos_forces: &mut DVector) {
        let ws = &mut self.workspace;
        let accelerations = self.accelerations.as_mut_slice();
        let pos_forces = pos_forces.as_mut_slice();
        for i in (0..self.links.len()).rev() {
            let link = &self.links[i];
            let jacobian = self.body_jacobians[i].as_slice();
            let [force, torque] = ws.wrenches[i];
            let [applied_force, applied_torque] = if applied {
                ws.applied_wrenches[i]
            } else {
                [Vector::ZERO; 2]
            };
            for c in link.assembly_id..link.assembly_id + link.joint.ndofs() {
                let jv = vec3_at(jacobian, c * SPATIAL_DIM);
                let jw = vec3_at(jacobian, c * SPATIAL_DIM + DIM);
                accelerations[c] = jv.dot(force) + jw.dot(torque);
                if applied {
                    pos_forces[c] = jv.dot(applied_force) + jw.dot(applied_torque);
                }
            }
            if i != 0 {
                // From this link's centre of mass to its parent's.
                let to_parent = link.shift02 + link.shift23;
                let parent = link.parent_internal_id;
                let [parent_force, parent_torque] = &mut ws.wrenches[parent];
                *parent_force += force;
                *parent_torque += torque + to_parent.cross(force);
                if applied {
                    let [parent_force, parent_torque] = &mut ws.applied_wrenches[parent];
                    *parent_force += applied_force;
                    *parent_torque += applied_torque + to_parent.cross(applied_force);
                }
            }
        }
    }

    // If the semi-implicit coriolis solve introduces more energy than the external
    // forces’ work, we recalculate without the coriolis term in the mass matrix.
    //
    // This operates by calculating the effective kinematic energy added by the
    // external forces after the solve with the semi-implicit mass matrix, and
    // compare it with the force’s work. If the energy delta exceeds a threshold
    // (indicating undesired/unrealistic energy injection), we fall back to re-solving
    // the forces effect but using only the mass matrix without the implicit coriolis
    // terms.
    fn free_velocity_energy_guard(&mut self, dt: Real, gen_forces: &DVector, pos_forces: &DVector) {
        let eff_dim = self.augmented_mass_indices.dim_after_removal(self.ndofs);
        if eff_dim == 0 {
            return;
        }

        // Move all quantities to the kinematic-reduced ordering of the
        // factorized matrices (no-op when there is no kinematic dof), in reused
        // buffers (gymfleet patch, see `PATCHES.md`).
        let ws = &mut self.workspace;
        for (buffer, source) in [
            (&mut ws.guard_v, &self.velocities),
            (&mut ws.guard_f, gen_forces),
            (&mut ws.guard_f_pos, pos_forces),
            (&mut ws.guard_a, &self.accelerations),
        ] {
            resize_zeroed(buffer, self.ndofs);
            buffer.copy_from(source);
            self.augmented_mass_indices.rearrange_rows(buffer, true);
        }
        resize_zeroed(&mut ws.guard_m_x, self.ndofs);

        let m = self.augmented_mass.view((0, 0), (eff_dim, eff_dim));
        let v = ws.guard_v.rows(0, eff_dim);
        let f = ws.guard_f.rows(0, eff_dim);
        let f_pos = ws.guard_f_pos.rows(0, eff_dim);
        let a = ws.guard_a.rows(0, eff_dim);
        let mut m_x = ws.guard_m_x.rows_mut(0, eff_dim);

        let excess = if a.iter().all(|x| x.is_finite()) {
            m_x.gemv(1.0, &m, &a, 0.0);
            let energy_delta = dt * v.dot(&m_x) + 0.5 * dt * dt * a.dot(&m_x);
            let work = dt * v.dot(&f) + 0.5 * dt * dt * a.dot(&f_pos);
            // Margin: a small fraction of the current kinetic energy to absorb
            // discretization error on healthy steps.
            m_x.gemv(1.0, &m, &v, 0.0);
            let kinetic_energy = 0.5 * v.dot(&m_x);
            let energy_margin = 1.0e-2 * kinetic_energy + 1.0e-8;
            Some(energy_delta - work - energy_margin)
        } else {
            None
        };

        match excess {
            Some(excess) if excess <= 0.0 => (), // Implicit update didn’t introduce too much extra energy.
            _ => {
                // The implicit solve injected energy (or produced non-finite
                // values): fall back to the plain mass matrix.
                self.factorize_inv_augmented_mass();
                self.accelerations.copy_from(gen_forces);
                self.augmented_mass_indices.with_rearranged_rows_mut(
                    &mut self.accelerations,
                    |accs| {
                        self.inv_augmented_mass.solve_mut(accs);
                    },
                );

                // Last-chance check: if all else fails, just clear the accelerations vector
                // instead of breaking the simulation. Hopefully it will get back to a
                // sane result in a close timestep.
                if !self.accelerations.iter().all(|x| x.is_finite()) {
                    self.accelerations.fill(0.0);
                }
            }
        }
    }

    /// Sets the rigid-body velocities of this multibody's links from its generalized
    /// velocities (gymfleet patch, see `PATCHES.md`). The solver does this at the start of
    /// every substep, so after a pipeline step the bodies' velocities are those before the
    /// last substep; call this after the step to read the final ones. The dynamics do not
    /// depend on it (the next substep recomputes them).
    pub fn update_rigid_body_velocities(&mut self, bodies: &mut RigidBodySet) {
        self.update_velocities(bodies);
    }

    /// Computes the links' velocities from the generalized velocities and writes them to
    /// their rigid bodies (after [`Self::forward_kinematics`] placed the links).
    ///
    /// gymfleet patch 41 (see `PATCHES.md`): public, so that generalized velocities set
    /// outside a step reach the rigid bodies before the next one.
    #[profiling::function]
    pub fn update_velocities(&mut self, bodies: &mut RigidBodySet) {
        /*
         * Compute velocities.
         * NOTE: this is needed for kinematic bodies too.
         */
        let link = &mut self.links[0];
        let joint_velocity = link
            .joint
            .jacobian_mul_coordinates(&self.velocities.as_slice()[link.assembly_id..]);

        link.joint_velocity = joint_velocity;
        // gymfleet patch (see `PATCHES.md`): a free root's linear DoFs move its frame's
        // origin; its centre of mass moves with them and with its turn about that origin.
        let mut root_vels = link.joint_velocity;
        root_vels.linvel += link.joint_velocity.angvel.gcross(link.shift23);
        bodies.index_mut_internal(link.rigid_body).vels = root_vels;

        for i in 1..self.links.len() {
            let (link, parent_link) = self.links.get_mut_with_parent(i);
            let rb = &bodies[link.rigid_body];
            let parent_rb = &bodies[parent_link.rigid_body];

            let joint_velocity = link
                .joint
                .jacobian_mul_coordinates(&self.velocities.as_slice()[link.assembly_id..]);
            link.joint_velocity = joint_velocity.transformed(
                &(parent_link.local_to_world.rotation * link.joint.data.local_frame1.rotation),
            );
            let mut new_rb_vels = parent_rb.vels + link.joint_velocity;
            let shift = rb.mprops.world_com - parent_rb.mprops.world_com;
            new_rb_vels.linvel += parent_rb.vels.angvel.gcross(shift);
            new_rb_vels.linvel += link.joint_velocity.angvel.gcross(link.shift23);

            bodies.index_mut_internal(link.rigid_body).vels = new_rb_vels;
        }
    }

    fn update_body_jacobians(&mut self) {
        for i in 0..self.links.len() {
            if self.body_jacobians[i].ncols() != self.ndofs {
                // TODO: use a resize instead.
                self.body_jacobians[i] = Jacobian::zeros(self.ndofs);
            }

            // NOTE (gymfleet patch, see `PATCHES.md`): a body jacobian is non-zero only on its
            //       link's span (the DoFs of the link and of its ancestors, all before it in
            //       assembly order), so the shifts below only touch those columns, and it is
            //       written on the contiguous storage: the parent's span copied, the rest
            //       zeroed, then the link's own columns written in place.
            let link = &self.links[i];
            let (start, ndofs, shift23) = (link.assembly_id, link.joint.ndofs(), link.shift23);
            let mut parent_span = 0;
            if i != 0 {
                let parent_id = link.parent_internal_id;
                let parent_link = &self.links[parent_id];
                parent_span = parent_link.assembly_id + parent_link.joint.ndofs();

                let (link_j, parent_j) = self.body_jacobians.index_mut_const(i, parent_id);
                let copied = parent_span * SPATIAL_DIM;
                link_j.as_mut_slice()[..copied].copy_from_slice(&parent_j.as_slice()[..copied]);
                // Jv += Jw × shift02: the parent's twists, seen at this link's joint.
                add_angular_cross_to_linear(link_j, 0..parent_span, link.shift02);
            }
            let jacobian = &mut self.body_jacobians[i];
            // Its siblings' columns (between its parent's span and its own) and the rest.
            jacobian.as_mut_slice()[parent_span * SPATIAL_DIM..start * SPATIAL_DIM].fill(0.0);
            jacobian.as_mut_slice()[(start + ndofs) * SPATIAL_DIM..].fill(0.0);
            // Jv += Jw × shift23: from the joint to the link's centre of mass.
            add_angular_cross_to_linear(jacobian, 0..parent_span, shift23);
            self.write_own_body_jacobian_columns(i);
        }
        self.body_jacobians_partial = false;
    }

    /// Only each link's own columns of its body jacobian (gymfleet patch 33, see
    /// `PATCHES.md`): [`Self::update_body_jacobians`] also writes its ancestors' columns. The
    /// other columns keep stale values until the next full update; `body_jacobians_partial`
    /// says so.
    #[cfg(feature = "dim3")]
    fn update_own_body_jacobian_columns(&mut self) {
        for i in 0..self.links.len() {
            if self.body_jacobians[i].ncols() != self.ndofs {
                self.body_jacobians[i] = Jacobian::zeros(self.ndofs);
            }
            self.write_own_body_jacobian_columns(i);
        }
        self.body_jacobians_partial = true;
    }

    /// Link `i`'s own columns of its body jacobian (those of its joint's DoFs, at its centre of
    /// mass), for both [`Self::update_body_jacobians`] and
    /// [`Self::update_own_body_jacobian_columns`] (gymfleet patch 33). Inlined: as a call per
    /// link it cost 0.4 % more instructions per HalfCheetah env step.
    #[inline(always)]
    fn write_own_body_jacobian_columns(&mut self, i: usize) {
        let link = &self.links[i];
        let parent_to_world = if i != 0 {
            self.links[link.parent_internal_id].local_to_world
        } else {
            Pose::IDENTITY
        };
        let (start, ndofs) = (link.assembly_id, link.joint.ndofs());
        let jacobian = &mut self.body_jacobians[i];
        jacobian.as_mut_slice()[start * SPATIAL_DIM..(start + ndofs) * SPATIAL_DIM].fill(0.0);
        link.joint.jacobian(
            &(parent_to_world.rotation * link.joint.data.local_frame1.rotation),
            &mut jacobian.columns_mut(start, ndofs),
        );
        // Jv += Jw × shift23: from the joint to the link's centre of mass.
        add_angular_cross_to_linear(jacobian, start..start + ndofs, link.shift23);
    }

    /// Debug builds check that the body jacobians are whole, not only their own columns
    /// (gymfleet patch 33), before a reader of the ancestors' columns.
    fn debug_assert_whole_body_jacobians(&self) {
        debug_assert!(
            !self.body_jacobians_partial,
            "the body jacobians hold only their own columns (gymfleet patch 33)"
        );
    }

    /// Adds link `i`'s contributions to the mass matrices (gymfleet patch, see `PATCHES.md`):
    /// `Jᵀ·diag(m, I)·J` to `augmented_mass`, and the velocity-dependent terms (the derivative of
    /// the gyroscopic forces and the coriolis terms, made semi-implicit) to
    /// `acc_augmented_mass`, on the link's span only. The same arithmetic as the generic 2D
    /// path, written column by column with the structure of each product.
    #[cfg(feature = "dim3")]
    fn accumulate_link_mass_3d(
        &mut self,
        i: usize,
        span: usize,
        dt: Real,
        velocity_terms: bool,
        bodies: &RigidBodySet,
    ) {
        if span == 0 {
            // A fixed root (or links welded to it): nothing moves it, it adds nothing.
            return;
        }
        let link = &self.links[i];
        let rb = &bodies[link.rigid_body];
        let (rb_mass, rb_inertia) = self.workspace.link_inertias[i];
        let rb_inertia = rb_inertia.into_matrix();
        let angvel = rb.vels.angvel;

        /*
         * Coriolis terms, column by column: `coriolis_v`/`coriolis_w` hold, for each DoF,
         * the linear/angular part of `JDot + JDot/u·qdot` of this link. Left out, with every
         * other velocity term, when the multibody is still (see `update_mass_matrix`).
         */
        if !velocity_terms {
            // Nothing to compute: `coriolis_v`/`coriolis_w` are not read below.
        } else if i != 0 {
            let parent_id = link.parent_internal_id;
            let parent_link = &self.links[parent_id];
            let parent_span = parent_link.assembly_id + parent_link.joint.ndofs();
            let parent_w = bodies[parent_link.rigid_body].vels.angvel;
            let parent_j = self.body_jacobians[parent_id].as_slice();
            let (coriolis_v, parent_coriolis_v) = self.coriolis_v.index_mut2(i, parent_id);
            let (coriolis_w, parent_coriolis_w) = self.coriolis_w.index_mut2(i, parent_id);
            let (cv, cw) = (coriolis_v.as_mut_slice(), coriolis_w.as_mut_slice());
            let (pcv, pcw) = (parent_coriolis_v.as_slice(), parent_coriolis_w.as_slice());

            let shift02 = link.shift02;
            // JDot (the 2.0 originates from the sum of two identical terms in JDot and
            // JDot/u * qdot), then JDot/u * qdot.
            let dvel = angvel.cross(shift02) + 2.0 * link.joint_velocity.linvel;
            let joint_linvel = link.joint_velocity.linvel;
            let joint_angvel = link.joint_velocity.angvel;
            for c in 0..parent_span {
                let parent_jw = vec3_at(parent_j, c * SPATIAL_DIM + DIM);
                let parent_cw = vec3_at(pcw, c * DIM);
                let v = vec3_at(pcv, c * DIM)
                    + parent_cw.cross(shift02)
                    + parent_jw.cross(dvel)
                    + parent_jw.cross(joint_linvel)
                    + parent_w.cross(parent_jw.cross(shift02));
                let w = parent_cw - joint_angvel.cross(parent_jw);
                set_vec3_at(cv, c * DIM, v);
                set_vec3_at(cw, c * DIM, w);
            }
            // Columns of this link's span past its parent's: its own DoFs (and, in a tree,
            // none of its siblings').
            cv[parent_span * DIM..span * DIM].fill(0.0);
            cw[parent_span * DIM..span * DIM].fill(0.0);

            if !link.joint.kinematic {
                let ndofs = link.joint.ndofs();
                let mut tmp = SMatrix::<Real, SPATIAL_DIM, SPATIAL_DIM>::zeros();
                let mut rb_joint_j = tmp.columns_mut(0, ndofs);
                link.joint.jacobian(
                    &(parent_link.local_to_world.rotation * link.joint.data.local_frame1.rotation),
                    &mut rb_joint_j,
                );
                for k in 0..ndofs {
                    let col = rb_joint_j.column(k);
                    let jv = Vector::new(col[0], col[1], col[2]);
                    let jw = Vector::new(col[3], col[4], col[5]);
                    let c = (link.assembly_id + k) * DIM;
                    set_vec3_at(cv, c, vec3_at(cv, c) + 2.0 * parent_w.cross(jv));
                    set_vec3_at(cw, c, vec3_at(cw, c) + parent_w.cross(jw));
                }
            }
        } else {
            self.coriolis_v[i].fill(0.0);
            self.coriolis_w[i].fill(0.0);
        }

        let rb_j = self.body_jacobians[i].as_slice();
        let cv = self.coriolis_v[i].as_mut_slice();
        let cw = self.coriolis_w[i].as_slice();
        let shift23 = link.shift23;
        let dvel23 = angvel.cross(shift23);

        /*
         * Per-column factors of both matrices:
         * `M[a, b] += jv_a·(m∘jv_b) + jw_a·(I·jw_b)` and
         * `X[a, b] += jv_a·(m·dt∘cv_b) + jw_a·(G·dt·jw_b + dt·I·cw_b)`,
         * with `G` the derivative of the gyroscopic forces.
         */
        let gyroscopic_dt =
            (angvel.gcross_matrix() * rb_inertia - (rb_inertia * angvel).gcross_matrix()) * dt;
        let mass_dt = rb_mass * dt;
        let ws = &mut self.workspace;
        if ws.mass_columns.len() < span {
            ws.mass_columns.resize(self.ndofs, MassColumn::default());
            for rows in &mut ws.jacobian_rows {
                rows.resize(self.ndofs, 0.0);
            }
        }
        for c in 0..span {
            let jv = vec3_at(rb_j, c * SPATIAL_DIM);
            let jw = vec3_at(rb_j, c * SPATIAL_DIM + DIM);
            for (rows, value) in ws
                .jacobian_rows
                .iter_mut()
                .zip([jv.x, jv.y, jv.z, jw.x, jw.y, jw.z])
            {
                rows[c] = value;
            }
            let (acc_v, acc_w) = if velocity_terms {
                let w = vec3_at(cw, c * DIM);
                // [c3 - c2].gcross() * (JDot + JDot/u * qdot), JDot, then JDot/u * qdot.
                let v = vec3_at(cv, c * DIM)
                    + w.cross(shift23)
                    + jw.cross(dvel23)
                    + angvel.cross(jw.cross(shift23));
                set_vec3_at(cv, c * DIM, v);
                (mass_dt * v, gyroscopic_dt * jw + rb_inertia * (w * dt))
            } else {
                (Vector::ZERO, Vector::ZERO)
            };
            ws.mass_columns[c] = MassColumn {
                mass_jv: rb_mass * jv,
                inertia_jw: rb_inertia * jw,
                acc_v,
                acc_w,
            };
        }

        // Column `b` of each product is a sum of the six jacobian rows (kept as contiguous
        // arrays, so that these loops vectorize) weighted by column `b`'s factors. The mass
        // matrix is symmetric: only its upper triangle is accumulated here (see
        // `update_mass_matrix`, which mirrors it).
        let n = self.ndofs;
        let mass = self.augmented_mass.as_mut_slice();
        let acc = self.acc_augmented_mass.as_mut_slice();
        let [jx, jy, jz, wx, wy, wz] = &ws.jacobian_rows;
        let (jx, jy, jz) = (&jx[..span], &jy[..span], &jz[..span]);
        let (wx, wy, wz) = (&wx[..span], &wy[..span], &wz[..span]);
        for (b, col) in ws.mass_columns[..span].iter().enumerate() {
            if velocity_terms {
                let (av, aw) = (col.acc_v, col.acc_w);
                let acc_col = &mut acc[b * n..b * n + span];
                for (a, out) in acc_col.iter_mut().enumerate() {
                    *out += jx[a] * av.x
                        + jy[a] * av.y
                        + jz[a] * av.z
                        + wx[a] * aw.x
                        + wy[a] * aw.y
                        + wz[a] * aw.z;
                }
            }
            let (mv, iw) = (col.mass_jv, col.inertia_jw);
            let mass_col = &mut mass[b * n..b * n + b + 1];
            for (a, out) in mass_col.iter_mut().enumerate() {
                *out += jx[a] * mv.x
                    + jy[a] * mv.y
                    + jz[a] * mv.z
                    + wx[a] * iw.x
                    + wy[a] * iw.y
                    + wz[a] * iw.z;
            }
        }
    }

    pub(crate) fn update_mass_matrix(&mut self, dt: Real, bodies: &RigidBodySet) {
        self.update_link_inertias(bodies);
        self.update_mass_matrix_with_link_inertias(dt, bodies);
    }

    /// [`Self::update_mass_matrix`] with `workspace.link_inertias` current.
    fn update_mass_matrix_with_link_inertias(&mut self, dt: Real, bodies: &RigidBodySet) {
        if self.ndofs == 0 {
            return; // Nothing to do.
        }

        if self.augmented_mass.ncols() != self.ndofs {
            // TODO: do a resize instead of a full reallocation.
            self.augmented_mass = DMatrix::zeros(self.ndofs, self.ndofs);
            self.acc_augmented_mass = DMatrix::zeros(self.ndofs, self.ndofs);
        } else {
            // On the contiguous storage (gymfleet patch, see `PATCHES.md`): nalgebra's
            // element-wise `fill` is several times slower.
            self.augmented_mass.as_mut_slice().fill(0.0);
            self.acc_augmented_mass.as_mut_slice().fill(0.0);
        }

        self.augmented_mass_indices.clear();

        // gymfleet patch (see `PATCHES.md`): the velocity-dependent terms (the semi-implicit
        // coriolis and gyroscopic derivatives, all proportional to a velocity) are left out when
        // no DoF moves by more than `NEGLIGIBLE_MOTION_PER_SUBSTEP` in this substep: they would
        // change the matrix by a fraction of that size, far below `Real`'s resolution. The
        // links' velocities are those of the DoFs (`update_velocities`: a root that is not
        // dynamic has none), and `!(x < y)` keeps the terms for non-finite velocities.
        // Explicit velocity terms (patch 26) leave them out always: `update_acceleration`
        // applies the forces themselves either way.
        #[cfg(feature = "dim3")]
        let velocity_terms = !self.explicit_velocity_terms
            && !(dt * self.velocities.amax() < NEGLIGIBLE_MOTION_PER_SUBSTEP);
        #[cfg(feature = "dim2")]
        let velocity_terms = !self.explicit_velocity_terms;
        self.velocity_terms_skipped = !velocity_terms;
        // gymfleet patch (see `PATCHES.md`): chains and trees of one-DoF joints on a fixed or free
        // root build both matrices by composite rigid bodies, after the loop below; without the
        // velocity terms, trees of joints of any number of DoFs build `M` so (patch 30), and
        // with them, trees whose joints of several DoFs are planar (patch 31).
        #[cfg(feature = "dim3")]
        let composite = self.composite_applies_at_link_inertias(velocity_terms);
        // The link-by-link construction reads the ancestors' columns of the body jacobians
        // (gymfleet patch 33).
        #[cfg(feature = "dim3")]
        if !composite && self.body_jacobians_partial {
            self.update_body_jacobians();
        }

        // Resize coriolis workspaces if the link count or number of DOFs change.
        let coriolis_ndofs = self.coriolis_v.first().map(|m| m.ncols());
        if self.coriolis_v.len() != self.links.len() || coriolis_ndofs != Some(self.ndofs) {
            self.coriolis_v = vec![OMatrix::<Real, Dim, Dyn>::zeros(self.ndofs); self.links.len()];
            self.coriolis_w =
                vec![OMatrix::<Real, AngDim, Dyn>::zeros(self.ndofs); self.links.len()];
            self.i_coriolis_dt = Jacobian::zeros(self.ndofs);
        }

        let mut curr_assembly_id = 0;

        // NOTE (gymfleet patch, see `PATCHES.md`): the mass matrix is accumulated as
        //       `M = Σ Jᵢᵀ·diag(mᵢ, Iᵢ)·Jᵢ` over the links, and only on the columns where a
        //       link's body jacobian can be non-zero: its own DoFs and its ancestors', which
        //       all come before it in assembly order (its "span"). `acc_augmented_mass` gets
        //       only the velocity-dependent terms (gyroscopic and coriolis derivatives) here;
        //       the symmetric part it shares with `augmented_mass` is added once at the end.
        for i in 0..self.links.len() {
            let link = &self.links[i];

            // NOTE: the mass matrix index reordering operates on the assumption that the assembly
            //       ids are traversed in order. This assert is here to ensure the assumption always
            //       hold.
            assert_eq!(
                curr_assembly_id, link.assembly_id,
                "Internal error: contiguity assumption on assembly_id does not hold."
            );
            curr_assembly_id += link.joint.ndofs();
            let span = curr_assembly_id;

            if link.joint.kinematic {
                for k in link.assembly_id..link.assembly_id + link.joint.ndofs() {
                    self.augmented_mass_indices.remove(k);
                }
            } else {
                for k in link.assembly_id..link.assembly_id + link.joint.ndofs() {
                    self.augmented_mass_indices.keep(k);
                }
            }

            #[cfg(feature = "dim3")]
            if !composite {
                self.accumulate_link_mass_3d(i, span, dt, velocity_terms, bodies);
            }
            #[cfg(feature = "dim2")]
            {
                let rb = &bodies[link.rigid_body];
                let rb_mass = rb.mprops.effective_mass();
                let rb_inertia = rb.mprops.effective_angular_inertia().into_matrix();
                let body_jacobian = &self.body_jacobians[i];
                {
                    #[allow(clippy::useless_conversion)] // Needed in 3D, no-op in 2D
                    let rb_mass_matrix = concat_rb_mass_matrix(rb_mass, rb_inertia.into());
                    self.augmented_mass.view_mut((0, 0), (span, span)).quadform(
                        1.0,
                        &rb_mass_matrix,
                        &body_jacobian.columns(0, span),
                        1.0,
                    );
                }

                /*
                 *
                 * Coriolis matrix.
                 *
                 */
                let rb_j = &self.body_jacobians[i];
                let rb_j_w = rb_j.view((DIM, 0), (ANG_DIM, span));

                let ndofs = link.joint.ndofs();

                if i != 0 {
                    let parent_id = link.parent_internal_id;
                    let parent_link = &self.links[parent_id];
                    let parent_span = parent_link.assembly_id + parent_link.joint.ndofs();
                    let parent_rb = &bodies[parent_link.rigid_body];
                    let parent_j = &self.body_jacobians[parent_id];
                    let parent_j_w = parent_j.view((DIM, 0), (ANG_DIM, parent_span));
                    let parent_w =
                        SimdAngVector::<Real>::from(parent_rb.vels.angvel).gcross_matrix();

                    let (coriolis_v, parent_coriolis_v) = self.coriolis_v.index_mut2(i, parent_id);
                    let (coriolis_w, parent_coriolis_w) = self.coriolis_w.index_mut2(i, parent_id);

                    // The parent's terms live on its span; this link's span adds its own DoFs
                    // (and, in a tree, skips its siblings'), so clear the rest of it.
                    coriolis_v
                        .columns_mut(0, parent_span)
                        .copy_from(&parent_coriolis_v.columns(0, parent_span));
                    coriolis_w
                        .columns_mut(0, parent_span)
                        .copy_from(&parent_coriolis_w.columns(0, parent_span));
                    coriolis_v.columns_range_mut(parent_span..span).fill(0.0);
                    coriolis_w.columns_range_mut(parent_span..span).fill(0.0);
                    let mut coriolis_v_p = coriolis_v.columns_mut(0, parent_span);
                    let mut coriolis_w_p = coriolis_w.columns_mut(0, parent_span);

                    // [c1 - c0].gcross() * (JDot + JDot/u * qdot)"
                    let shift_cross_tr = vect_to_na(link.shift02).gcross_matrix_tr();
                    coriolis_v_p.gemm(
                        1.0,
                        &shift_cross_tr,
                        &parent_coriolis_w.columns(0, parent_span),
                        1.0,
                    );

                    // JDot (but the 2.0 originates from the sum of two identical terms in JDot and JDot/u * gdot)
                    let dvel_cross = vect_to_na(
                        rb.vels.angvel.gcross(link.shift02) + 2.0 * link.joint_velocity.linvel,
                    )
                    .gcross_matrix_tr();
                    coriolis_v_p.gemm(1.0, &dvel_cross, &parent_j_w, 1.0);

                    // JDot/u * qdot
                    coriolis_v_p.gemm(
                        1.0,
                        &vect_to_na(link.joint_velocity.linvel).gcross_matrix_tr(),
                        &parent_j_w,
                        1.0,
                    );
                    coriolis_v_p.gemm(1.0, &(parent_w * shift_cross_tr), &parent_j_w, 1.0);

                    #[cfg(feature = "dim3")]
                    {
                        let vel_wrt_joint_w =
                            vect_to_na(link.joint_velocity.angvel).gcross_matrix();
                        coriolis_w_p.gemm(-1.0, &vel_wrt_joint_w, &parent_j_w, 1.0);
                    }
                    #[cfg(feature = "dim2")]
                    let _ = &mut coriolis_w_p;

                    // JDot (but the 2.0 originates from the sum of two identical terms in JDot and JDot/u * gdot)
                    if !link.joint.kinematic {
                        let mut coriolis_v_part = coriolis_v.columns_mut(link.assembly_id, ndofs);

                        let mut tmp1 = SMatrix::<Real, SPATIAL_DIM, SPATIAL_DIM>::zeros();
                        let mut rb_joint_j = tmp1.columns_mut(0, ndofs);
                        link.joint.jacobian(
                            &(parent_link.local_to_world.rotation
                                * link.joint.data.local_frame1.rotation),
                            &mut rb_joint_j,
                        );

                        let rb_joint_j_v = rb_joint_j.fixed_rows::<DIM>(0);
                        coriolis_v_part.gemm(2.0, &parent_w, &rb_joint_j_v, 1.0);

                        #[cfg(feature = "dim3")]
                        {
                            let rb_joint_j_w = rb_joint_j.fixed_rows::<ANG_DIM>(DIM);
                            let mut coriolis_w_part =
                                coriolis_w.columns_mut(link.assembly_id, ndofs);
                            coriolis_w_part.gemm(1.0, &parent_w, &rb_joint_j_w, 1.0);
                        }
                    }
                } else {
                    self.coriolis_v[i].fill(0.0);
                    self.coriolis_w[i].fill(0.0);
                }

                let (mut coriolis_v, coriolis_w) = (
                    self.coriolis_v[i].columns_mut(0, span),
                    self.coriolis_w[i].columns(0, span),
                );

                {
                    // [c3 - c2].gcross() * (JDot + JDot/u * qdot)
                    let shift_cross_tr = vect_to_na(link.shift23).gcross_matrix_tr();
                    coriolis_v.gemm(1.0, &shift_cross_tr, &coriolis_w, 1.0);

                    // JDot
                    let dvel_cross =
                        vect_to_na(rb.vels.angvel.gcross(link.shift23)).gcross_matrix_tr();
                    coriolis_v.gemm(1.0, &dvel_cross, &rb_j_w, 1.0);

                    // JDot/u * qdot
                    coriolis_v.gemm(
                        1.0,
                        &(SimdAngVector::<Real>::from(rb.vels.angvel).gcross_matrix()
                            * shift_cross_tr),
                        &rb_j_w,
                        1.0,
                    );
                }

                /*
                 * Meld with the mass matrix.
                 */
                {
                    let mut i_coriolis_dt_v = self.i_coriolis_dt.fixed_rows_mut::<DIM>(0);
                    let mut i_coriolis_dt_v = i_coriolis_dt_v.columns_mut(0, span);
                    i_coriolis_dt_v.copy_from(&coriolis_v);
                    let rb_mass_dt = vect_to_na(rb_mass * dt);
                    i_coriolis_dt_v
                        .column_iter_mut()
                        .for_each(|mut c| c.component_mul_assign(&rb_mass_dt));
                }

                #[cfg(feature = "dim2")]
                {
                    let mut i_coriolis_dt_w = self.i_coriolis_dt.fixed_rows_mut::<ANG_DIM>(DIM);
                    // NOTE: this is just an axpy, but on row columns.
                    i_coriolis_dt_w
                        .columns_mut(0, span)
                        .zip_apply(&coriolis_w, |o, x| *o = x * dt * rb_inertia);
                }
                #[cfg(feature = "dim3")]
                {
                    let mut i_coriolis_dt_w = self.i_coriolis_dt.fixed_rows_mut::<ANG_DIM>(DIM);
                    i_coriolis_dt_w.columns_mut(0, span).gemm(
                        dt,
                        &mat_to_na(rb_inertia),
                        &coriolis_w,
                        0.0,
                    );
                }

                self.acc_augmented_mass
                    .view_mut((0, 0), (span, span))
                    .gemm_tr(
                        1.0,
                        &rb_j.columns(0, span),
                        &self.i_coriolis_dt.columns(0, span),
                        1.0,
                    );
            }
        }

        #[cfg(feature = "dim3")]
        if composite {
            self.composite_mass_matrices(dt, velocity_terms, bodies);
        }

        // The 3D path accumulates only the upper triangle of the symmetric mass matrix (the
        // composite construction of `M` alone writes both: gymfleet patch 35).
        #[cfg(feature = "dim3")]
        if !composite || velocity_terms {
            let n = self.ndofs;
            let mass = self.augmented_mass.as_mut_slice();
            for b in 0..n {
                for a in 0..b {
                    mass[b + a * n] = mass[a + b * n];
                }
            }
        }

        /*
         * Damping and armature.
         *
         * Damping is a velocity-proportional force made implicit, so it adds
         * `dt · d` to the mass-matrix diagonal. Armature is a "reflected
         * rotor inertia" (additional inertia to account for the joint’s
         * mass and geometry itself): it adds to the diagonal directly.
         */
        // gymfleet patch 50: with the damping after the constraints (and no kinematic DoF,
        // whose removal would reorder the matrix), `M` keeps only the armature here; the
        // damping enters `M + dt·D`, factorized below for the step's end.
        let damping_after = self.damping_after_active.is_some()
            && self.augmented_mass_indices.dim_after_removal(self.ndofs) == self.ndofs;
        if !damping_after {
            self.damping_after_active = None;
        }
        for i in 0..self.ndofs {
            let diag = if damping_after {
                self.armature[i]
            } else {
                self.damping[i] * dt + self.armature[i]
            };
            self.augmented_mass[(i, i)] += diag;
        }

        // Implicit joint springs: `dt²·k` on the mass-matrix diagonal (force term in `update_acceleration`)
        // keeps a stiff spring on a low-inertia link stable where an explicit position motor injects energy.
        // The spring lives on the link's `MultibodyJoint` so it travels with the link through topology changes.
        // gymfleet patch 45: explicit springs leave the matrix alone.
        let dt2 = if self.explicit_springs { 0.0 } else { dt * dt };
        for link in self.links.iter() {
            for (a, idx) in free_axes(&link.joint, link.assembly_id) {
                let k = link.joint.spring_stiffness[a];
                if k != 0.0 {
                    self.augmented_mass[(idx, idx)] += k * dt2;
                }
            }
        }

        // The part both matrices share (on the contiguous storage, gymfleet patch).
        for (acc, mass) in self
            .acc_augmented_mass
            .as_mut_slice()
            .iter_mut()
            .zip(self.augmented_mass.as_slice())
        {
            *acc += *mass;
        }

        let effective_dim = self
            .augmented_mass_indices
            .dim_after_removal(self.acc_augmented_mass.nrows());

        // PERF: since we clone the matrix anyway for LU, should be directly output
        //       a new matrix instead of applying permutations?
        self.augmented_mass_indices
            .rearrange_columns(&mut self.acc_augmented_mass, true);
        self.augmented_mass_indices
            .rearrange_rows(&mut self.acc_augmented_mass, true);
        if self.velocity_terms_skipped {
            // gymfleet patch 29: without the velocity terms the matrix is the plain one,
            // symmetric positive definite.
            self.acc_inv_augmented_mass
                .factorize_symmetric_leading(&self.acc_augmented_mass, effective_dim);
        } else {
            self.acc_inv_augmented_mass
                .factorize_leading(&self.acc_augmented_mass, effective_dim);
        }
        self.augmented_mass_indices
            .rearrange_columns(&mut self.augmented_mass, true);
        self.augmented_mass_indices
            .rearrange_rows(&mut self.augmented_mass, true);

        // gymfleet patch (see `PATCHES.md`): `inv_augmented_mass` serves only constraints and
        // hard limits; it is factorized on demand (`factorize_inv_augmented_mass`).
        self.inv_augmented_mass_stale = true;

        // gymfleet patch 50: `M + dt·D` (the damped matrix of Rapier's order) for the step's
        // end, and the velocities it starts from.
        if damping_after {
            let n = self.ndofs;
            if self.damped_mass.shape() != self.augmented_mass.shape() {
                self.damped_mass = self.augmented_mass.clone();
            } else {
                self.damped_mass.copy_from(&self.augmented_mass);
            }
            for i in 0..n {
                self.damped_mass[(i, i)] += self.damping[i] * dt;
            }
            self.inv_damped_mass
                .factorize_symmetric_leading(&self.damped_mass, n);
            if self.damping_start_velocities.len() != n {
                self.damping_start_velocities = DVector::zeros(n);
            }
            self.damping_start_velocities.copy_from(&self.velocities);
        }
    }

    /// Per-DoF inverse joint-space inertia `diag(M⁻¹)` at the current configuration, where `M`
    /// includes armature but excludes joint damping and springs — MuJoCo's `dof_invweight0`: the
    /// apparent inverse inertia at each DoF with all other DoFs free, including the articulated
    /// coupling. Re-runs forward kinematics and reassembles the mass matrix, so intended for
    /// occasional use (e.g. sizing `<joint springdamper>` springs at load time), not every step.
    pub fn dof_inverse_inertia(&mut self, bodies: &RigidBodySet) -> DVector {
        // Resolve the root joint type (a fixed base may still be a 6-DoF free root pre-collapse)
        // so `ndofs` is final, then assemble `M`. `dt = 0` drops the `dt·damping` and
        // `dt²·stiffness` diagonal terms, leaving exactly `M + armature`.
        self.forward_kinematics(bodies, false);
        self.update_mass_matrix(0.0, bodies);
        self.factorize_inv_augmented_mass();

        let n = self.ndofs;
        let mut out = DVector::zeros(n);
        if n == 0 {
            return out;
        }
        // `(M⁻¹)[i, i]` for each DoF: solve `M x = e_i` and read `x[i]`. The `inv_augmented_mass`
        // factorization lives in the kinematic-reduced ordering, so route the unit vector through
        // the same rearrangement the solver uses.
        let mut e = DVector::zeros(n);
        for i in 0..n {
            e.fill(0.0);
            e[i] = 1.0;
            self.augmented_mass_indices
                .with_rearranged_rows_mut(&mut e, |b| {
                    self.inv_augmented_mass.solve_mut(b);
                });
            out[i] = e[i];
        }
        out
    }

    /// Per-DoF joint-space inertia `diag(M)` at the current configuration, armature
    /// included, damping and springs excluded — MuJoCo's `dof_M0` when taken at the
    /// model's pose (gymfleet patch 38: sizes an actuator's damping from its `dampratio`).
    /// Re-runs forward kinematics and reassembles the mass matrix, so intended for
    /// occasional use, not every step. Removed (locked) DoFs read 0.
    pub fn dof_mass_diagonal(&mut self, bodies: &RigidBodySet) -> DVector {
        self.forward_kinematics(bodies, false);
        self.update_mass_matrix(0.0, bodies);
        let n = self.ndofs;
        let mut out = DVector::zeros(n);
        if n == 0 {
            return out;
        }
        // `augmented_mass` is kept in the kinematic-reduced ordering: read its diagonal
        // there, and route it back through the inverse rearrangement.
        let diagonal: Vec<Real> = (0..n).map(|i| self.augmented_mass[(i, i)]).collect();
        self.augmented_mass_indices
            .with_rearranged_rows_mut(&mut out, |b| {
                for (i, value) in b.iter_mut().enumerate() {
                    *value = diagonal[i];
                }
            });
        out
    }

    /// Adds a holonomic coupling between two of this multibody's generalized
    /// coordinates (`q2 = coeff·q1 + offset`), enforced as a velocity-level
    /// equality constraint each step. See [`MultibodyDofCoupling`].
    pub fn add_dof_coupling(&mut self, coupling: MultibodyDofCoupling) {
        self.couplings.push(coupling);
    }

    /// The DoF couplings declared on this multibody.
    ///
    /// Couplings follow the multibody's topology changes (link insertions, merges and splits);
    /// a coupling is dropped once one of its DoFs no longer exists, or when its two DoFs end up
    /// in different multibodies.
    pub fn couplings(&self) -> &[MultibodyDofCoupling] {
        &self.couplings
    }

    /// Removes the `i`-th DoF coupling (in the order of [`Self::couplings`]) and returns it.
    ///
    /// Returns `None` if there is no such coupling. The couplings after it shift down by one.
    pub fn remove_dof_coupling(&mut self, i: usize) -> Option<MultibodyDofCoupling> {
        (i < self.couplings.len()).then(|| self.couplings.remove(i))
    }

    /// Keeps only the DoF couplings for which `f` returns `true`.
    pub fn retain_dof_couplings(&mut self, f: impl FnMut(&MultibodyDofCoupling) -> bool) {
        self.couplings.retain(f);
    }

    /// Removes all the DoF couplings of this multibody.
    pub fn clear_dof_couplings(&mut self) {
        self.couplings.clear();
    }

    /// The number of dry-friction rows `link_id`'s joint will emit: one per
    /// free DoF whose `frictionloss` entry is non-zero.
    pub(crate) fn num_friction_constraints(&self, link_id: usize) -> usize {
        let Some(link) = self.link(link_id) else {
            return 0;
        };
        let ndofs = link.joint().ndofs();
        (0..ndofs)
            .filter(|i| self.frictions[link.assembly_id + i] > 0.0)
            .count()
    }

    /// Number of coupling constraints "owned" by `owner_link` — couplings whose first joint
    /// (`link1`) is that link. Each coupling is generated once, by `link1` (which always has a
    /// free DoF and so is an active link in the solver island, unlike a possibly-fixed root).
    pub(crate) fn num_couplings_owned_by(&self, owner_link: usize) -> usize {
        self.couplings
            .iter()
            .filter(|c| c.link1 == owner_link)
            .count()
    }

    /// Generates the velocity constraints for the DoF couplings owned by `owner_link` into
    /// `out[..]`: each coupling `q2 = coeff·q1 + offset` is one bilateral constraint with jacobian
    /// `J = e_{q2} − coeff·e_{q1}` and a rhs pulling the position drift back to zero.
    pub(crate) fn coupling_velocity_constraints(
        &self,
        owner_link: usize,
        params: &IntegrationParameters,
        mut j_id: usize,
        jacobians: &mut DVector,
        out: &mut [GenericJointConstraint],
    ) -> usize {
        let ndofs = self.ndofs;
        let erp_inv_dt = SpringCoefficients::<Real>::joint_defaults().erp_inv_dt(params.dt);

        let mut i = 0;
        for c in self.couplings.iter().filter(|c| c.link1 == owner_link) {
            let g1 = self.links[c.link1].assembly_id + c.dof1;
            let g2 = self.links[c.link2].assembly_id + c.dof2;
            let q1 = self.links[c.link1].joint().coords()[c.axis1];
            let q2 = self.links[c.link2].joint().coords()[c.axis2];

            // Jacobian J = e_{g2} − coeff·e_{g1}, then WJ = M⁻¹ J.
            jacobians.rows_mut(j_id, ndofs * 2).fill(0.0);
            jacobians[j_id + g2] += 1.0;
            jacobians[j_id + g1] -= c.coeff;
            for k in 0..ndofs {
                jacobians[j_id + ndofs + k] = jacobians[j_id + k];
            }
            self.inv_augmented_mass()
                .solve_mut(&mut jacobians.rows_mut(j_id + ndofs, ndofs));

            // lhs = Jᵀ M⁻¹ J = Σ J[k]·WJ[k]; only g1/g2 entries of J are nonzero.
            let lhs = jacobians[j_id + ndofs + g2] - c.coeff * jacobians[j_id + ndofs + g1];

            let drift = q2 - c.coeff * q1 - c.offset;

            out[i] = GenericJointConstraint {
                is_rigid_body1: false,
                solver_vel1: u32::MAX,
                ndofs1: 0,
                j_id1: 0,
                is_rigid_body2: false,
                solver_vel2: self.solver_id,
                ndofs2: ndofs,
                j_id2: j_id,
                joint_id: usize::MAX, // internal: no impulse writeback.
                impulse: 0.0,
                impulse_bounds: [-Real::MAX, Real::MAX],
                inv_lhs: crate::utils::inv(lhs),
                rhs: drift * erp_inv_dt,
                rhs_wo_bias: 0.0,
                cfm_coeff: 0.0,
                cfm_gain: 0.0,
                writeback_id: WritebackId::Dof(0),
            };

            j_id += 2 * ndofs;
            i += 1;
        }

        i
    }

    /// The generalized velocity at the multibody_joint of the given link.
    #[inline]
    pub fn joint_velocity(&self, link: &MultibodyLink) -> DVectorView<'_, Real> {
        let ndofs = link.joint().ndofs();
        DVectorView::from_slice(
            &self.velocities.as_slice()[link.assembly_id..link.assembly_id + ndofs],
            ndofs,
        )
    }

    /// The generalized accelerations of this multibodies.
    #[inline]
    pub fn generalized_acceleration(&self) -> DVectorView<'_, Real> {
        self.accelerations.rows(0, self.ndofs)
    }

    /// gymfleet patch 43: MuJoCo's `body_invweight0` of link `link_id` at the current
    /// configuration: the means of the translational and of the rotational diagonal of
    /// `J·M⁻¹·Jᵀ`, `J` the link's body jacobian (its centre of mass's velocity and its angular
    /// velocity). Like [`Self::dof_inverse_inertia`], for occasional use.
    pub fn body_invweight(&mut self, bodies: &RigidBodySet, link_id: usize) -> (Real, Real) {
        self.forward_kinematics(bodies, false);
        self.update_mass_matrix(0.0, bodies);
        self.factorize_inv_augmented_mass();
        let n = self.ndofs;
        if n == 0 || link_id >= self.links.len() {
            return (0.0, 0.0);
        }
        let jacobian = self.body_jacobians[link_id].clone();
        let mut diagonal = [0.0; SPATIAL_DIM];
        let mut x = DVector::zeros(n);
        for (row, out) in diagonal.iter_mut().enumerate() {
            for k in 0..n {
                x[k] = jacobian[(row, k)];
            }
            self.augmented_mass_indices
                .with_rearranged_rows_mut(&mut x, |b| {
                    self.inv_augmented_mass.solve_mut(b);
                });
            *out = (0..n).map(|k| jacobian[(row, k)] * x[k]).sum();
        }
        let tran = (diagonal[0] + diagonal[1] + diagonal[2]) / 3.0;
        let rot = diagonal[DIM..].iter().sum::<Real>() / ANG_DIM as Real;
        (tran, rot)
    }

    /// The generalized velocities of this multibodies.
    #[inline]
    pub fn generalized_velocity(&self) -> DVectorView<'_, Real> {
        self.velocities.rows(0, self.ndofs)
    }

    /// The body jacobian for link `link_id` calculated by the last call to [`Multibody::forward_kinematics`].
    #[inline]
    pub fn body_jacobian(&self, link_id: usize) -> &Jacobian<Real> {
        self.debug_assert_whole_body_jacobians();
        &self.body_jacobians[link_id]
    }

    /// The mutable generalized velocities of this multibodies.
    #[inline]
    pub fn generalized_velocity_mut(&mut self) -> DVectorViewMut<'_, Real> {
        self.velocities.rows_mut(0, self.ndofs)
    }

    #[inline]
    pub(crate) fn integrate(&mut self, dt: Real) {
        for rb in self.links.iter_mut() {
            rb.joint
                .integrate(dt, &self.velocities.as_slice()[rb.assembly_id..])
        }
    }

    /// Hard limits (see [`Multibody::set_hard_limits`]): puts every limited DoF found past a
    /// limit back exactly on it, and removes its outward velocity by an inelastic generalized
    /// impulse through the mass matrix factorized for this substep. Kinematic DoFs and the
    /// coupled angular DoFs of ball-like joints (whose coordinates are not geometric) are left
    /// to the limit constraint. Returns whether any generalized velocity changed.
    pub(crate) fn project_hard_limits(&mut self, bodies: &RigidBodySet) -> bool {
        let mut velocity_changed = false;
        for i in 0..self.links.len() {
            let joint = &self.links[i].joint;
            let locked = joint.data.locked_axes.bits();
            let limited = joint.data.limit_axes.bits() & !locked;
            // gymfleet patch 44: compliant limits are solver rows, not projections.
            if limited == 0 || joint.kinematic || joint.limit_compliance.is_some() {
                continue;
            }
            let num_free_ang = ANG_DIM - ((locked >> DIM).count_ones() as usize);
            let mut dof = self.links[i].assembly_id;
            for axis in 0..SPATIAL_DIM {
                if locked & (1 << axis) != 0 {
                    continue;
                }
                let this_dof = dof;
                dof += 1;
                if limited & (1 << axis) == 0 || (axis >= DIM && num_free_ang != 1) {
                    continue;
                }
                let joint = &mut self.links[i].joint;
                let limits = joint.data.limits[axis];
                let q = joint.coords[axis];
                let (bound, outward) = if q > limits.max {
                    (limits.max, 1.0)
                } else if q < limits.min {
                    (limits.min, -1.0)
                } else {
                    continue;
                };
                joint.set_single_coord(axis, bound);
                velocity_changed |= self.stop_outward_velocity(this_dof, outward);
            }
        }
        for k in 0..self.linear_limits.len() {
            velocity_changed |= self.project_linear_limit(k);
        }
        if !self.path_limits.is_empty() {
            // The links where the coordinates now put them (the solver's own forward
            // kinematics follows the projections).
            self.forward_kinematics(bodies, false);
            for k in 0..self.path_limits.len() {
                velocity_changed |= self.project_path_limit(k, bodies);
            }
        }
        velocity_changed
    }

    /// Rope `k` (gymfleet patch 42): see [`Multibody::set_path_limits`].
    fn project_path_limit(&mut self, k: usize, bodies: &RigidBodySet) -> bool {
        let limit = &self.path_limits[k];
        let world: Vec<Vector> = limit
            .points
            .iter()
            .map(|&(link, p)| match link {
                Some(id) => self.links[id].local_to_world * p,
                None => p,
            })
            .collect();
        let length: Real = world.windows(2).map(|w| (w[1] - w[0]).length()).sum();
        if length <= limit.max {
            return false;
        }
        // The length's jacobian: each segment's direction at its two ends.
        let mut j = DVector::zeros(self.ndofs);
        for (i, w) in world.windows(2).enumerate() {
            let along = w[1] - w[0];
            let len = along.length();
            if len <= Real::EPSILON {
                continue;
            }
            let dir = along / len;
            self.add_point_jacobian(&mut j, limit.points[i + 1].0, w[1], dir, bodies);
            self.add_point_jacobian(&mut j, limit.points[i].0, w[0], -dir, bodies);
        }
        let max = limit.max;
        self.factorize_inv_augmented_mass();
        let mut response = j.clone();
        let lu = &self.inv_augmented_mass;
        let mut solved = false;
        self.augmented_mass_indices
            .with_rearranged_rows_mut(&mut response, |r| solved = lu.solve_mut(r));
        let inv_mass = j.dot(&response);
        if !(solved && inv_mass > 0.0 && inv_mass.is_finite()) {
            return false;
        }
        // Back to the length, to first order, the way the masses give least.
        let displacement = &response * ((max - length) / inv_mass);
        self.apply_displacements(displacement.as_slice());
        // The lengthening rate removed.
        let rate = j.dot(&self.velocities);
        if rate <= 0.0 {
            return false;
        }
        self.velocities.axpy(-rate / inv_mass, &response, 1.0);
        true
    }

    /// Adds to `j` the generalized row of `dir · v`, `v` the velocity of world point `p` moving
    /// with link `link` (none: a fixed point), from the link's body jacobian at its centre of
    /// mass: `dir · v_com + ω · ((p − com) × dir)`.
    fn add_point_jacobian(
        &self,
        j: &mut DVector,
        link: Option<usize>,
        p: Vector,
        dir: Vector,
        bodies: &RigidBodySet,
    ) {
        let Some(id) = link else { return };
        let link = &self.links[id];
        let com = link.local_to_world * bodies[link.rigid_body].mprops.local_mprops.local_com;
        let arm = (p - com).cross(dir);
        let columns = self.body_jacobians[id].as_slice().chunks_exact(SPATIAL_DIM);
        for (entry, c) in j.iter_mut().zip(columns) {
            *entry += dir.x * c[0] + dir.y * c[1] + dir.z * c[2]
                + arm.x * c[3]
                + arm.y * c[4]
                + arm.z * c[5];
        }
    }

    /// The coordinate axis of a link's `local`-th free DoF.
    fn free_axis(&self, link: usize, local: usize) -> Option<usize> {
        let locked = self.links.get(link)?.joint.data.locked_axes.bits();
        (0..SPATIAL_DIM)
            .filter(|axis| locked & (1 << axis) == 0)
            .nth(local)
    }

    /// Linear limit `k` (gymfleet patch 20): see [`Multibody::set_linear_limits`].
    fn project_linear_limit(&mut self, k: usize) -> bool {
        let limit = &self.linear_limits[k];
        let mut value = 0.0;
        let mut norm2 = 0.0;
        for &(link, local, coef) in &limit.dofs {
            let Some(axis) = self.free_axis(link, local) else {
                return false;
            };
            value += coef * self.links[link].joint.coords[axis];
            norm2 += coef * coef;
        }
        // An equality (`min == max`, gymfleet patch 42) holds both ways: put back on its
        // value and all its rate removed, whichever side it is found on.
        let equality = limit.min == limit.max;
        let (bound, outward) = if value > limit.max {
            (limit.max, 1.0)
        } else if value < limit.min {
            (limit.min, -1.0)
        } else if equality {
            (limit.min, 0.0)
        } else {
            return false;
        };
        if norm2 <= 0.0 {
            return false;
        }
        // Back on the bound along the combination's own coefficients.
        let shift = (bound - value) / norm2;
        let dofs = limit.dofs.clone();
        for &(link, local, coef) in &dofs {
            let axis = self.free_axis(link, local).expect("checked above");
            let q = self.links[link].joint.coords[axis];
            self.links[link].joint.set_single_coord(axis, q + shift * coef);
        }
        // The outward rate removed through the mass matrix.
        let mut j = DVector::zeros(self.ndofs);
        for &(link, local, coef) in &dofs {
            j[self.links[link].assembly_id + local] += coef;
        }
        let rate = j.dot(&self.velocities);
        if if equality { rate == 0.0 } else { rate * outward <= 0.0 } {
            return false;
        }
        self.factorize_inv_augmented_mass();
        let mut response = j.clone();
        let lu = &self.inv_augmented_mass;
        let mut solved = false;
        self.augmented_mass_indices
            .with_rearranged_rows_mut(&mut response, |r| solved = lu.solve_mut(r));
        let inv_mass = j.dot(&response);
        if solved && inv_mass > 0.0 && inv_mass.is_finite() {
            self.velocities.axpy(-rate / inv_mass, &response, 1.0);
        }
        true
    }

    /// If DoF `dof` moves in direction `outward`, applies the generalized impulse along it that
    /// brings its velocity to zero: `Δv = M⁻¹·e·p` with `p = -v / (M⁻¹)ᵢᵢ`.
    fn stop_outward_velocity(&mut self, dof: usize, outward: Real) -> bool {
        let v = self.velocities[dof];
        if v * outward <= 0.0 {
            return false;
        }
        // gymfleet patch (see `PATCHES.md`): factorized on demand.
        self.factorize_inv_augmented_mass();
        let response = &mut self.workspace.ndofs_vec;
        if response.len() != self.ndofs {
            // The root's joint type (free or fixed) changes the DoF count after `add_link`.
            *response = DVector::zeros(self.ndofs);
        }
        response.fill(0.0);
        response[dof] = 1.0;
        let lu = &self.inv_augmented_mass;
        let mut solved = false;
        self.augmented_mass_indices
            .with_rearranged_rows_mut(response, |r| solved = lu.solve_mut(r));
        let inv_inertia = response[dof];
        if solved && inv_inertia > 0.0 && inv_inertia.is_finite() {
            let impulse = -v / inv_inertia;
            self.velocities.axpy(impulse, response, 1.0);
            // gymfleet patch 17 (see `PATCHES.md`): kept for the constraint-force readout.
            if self.hard_limit_impulses.len() != self.ndofs {
                self.hard_limit_impulses = DVector::zeros(self.ndofs);
            }
            self.hard_limit_impulses[dof] += impulse;
        } else {
            // A singular mass matrix: stop this DoF alone.
            self.velocities[dof] = 0.0;
        }
        true
    }

    /// The generalized impulse (N·s on a linear DoF, N·m·s on an angular one) the hard
    /// limits (see [`Multibody::set_hard_limits`]) applied to the DoFs of `link`'s joint
    /// since the last [`Multibody::clear_hard_limit_impulses`]: divided by the time elapsed,
    /// the limits' generalized constraint force (MuJoCo's `qfrc_constraint` of a limited
    /// joint). Zeros where no limit stopped a DoF (gymfleet patch 17, see `PATCHES.md`).
    pub fn hard_limit_impulses(&self, link: &MultibodyLink) -> impl Iterator<Item = Real> + '_ {
        let ndofs = link.joint().ndofs();
        (link.assembly_id..link.assembly_id + ndofs)
            .map(|i| self.hard_limit_impulses.get(i).copied().unwrap_or(0.0))
    }

    /// Adds `impulse` to DoF `dof`'s entry of [`Multibody::hard_limit_impulses`]: a compliant
    /// limit's generalized impulse over a substep (gymfleet patch 44).
    pub(crate) fn add_limit_impulse(&mut self, dof: usize, impulse: Real) {
        if self.hard_limit_impulses.len() != self.ndofs {
            self.hard_limit_impulses = DVector::zeros(self.ndofs);
        }
        if dof < self.ndofs {
            self.hard_limit_impulses[dof] += impulse;
        }
    }

    /// Starts a new accumulation of [`Multibody::hard_limit_impulses`] (gymfleet patch 17).
    pub fn clear_hard_limit_impulses(&mut self) {
        self.hard_limit_impulses.fill(0.0);
    }

    /// Apply displacements, in generalized coordinates, to this multibody.
    ///
    /// Note this does **not** updates the link poses, only their generalized coordinates.
    /// To update the link poses and associated rigid-bodies, call [`Self::forward_kinematics`].
    pub fn apply_displacements(&mut self, disp: &[Real]) {
        self.kinematics_current = false;
        for link in self.links.iter_mut() {
            link.joint.apply_displacement(&disp[link.assembly_id..])
        }
    }

    pub(crate) fn update_root_type(&mut self, bodies: &RigidBodySet, take_body_pose: bool) {
        if let Some(rb) = bodies.get(self.links[0].rigid_body) {
            if rb.is_dynamic() != self.root_is_dynamic {
                let root_pose = if take_body_pose {
                    *rb.position()
                } else {
                    self.links[0].local_to_world
                };

                if rb.is_dynamic() {
                    let free_joint = MultibodyJoint::free(root_pose);
                    let prev_root_ndofs = self.links[0].joint().ndofs();
                    self.links[0].joint = free_joint;
                    self.links[0].assembly_id = 0;
                    self.ndofs += SPATIAL_DIM;

                    self.velocities = self.velocities.clone().insert_rows(0, SPATIAL_DIM, 0.0);
                    self.damping = self.damping.clone().insert_rows(0, SPATIAL_DIM, 0.0);
                    self.armature = self.armature.clone().insert_rows(0, SPATIAL_DIM, 0.0);
                    self.frictions = self.frictions.clone().insert_rows(0, SPATIAL_DIM, 0.0);
                    self.applied_forces =
                        self.applied_forces.clone().insert_rows(0, SPATIAL_DIM, 0.0);
                    self.accelerations =
                        self.accelerations.clone().insert_rows(0, SPATIAL_DIM, 0.0);

                    for link in &mut self.links[1..] {
                        link.assembly_id += SPATIAL_DIM - prev_root_ndofs;
                    }
                } else {
                    assert!(self.velocities.len() >= SPATIAL_DIM);
                    assert!(self.damping.len() >= SPATIAL_DIM);
                    assert!(self.armature.len() >= SPATIAL_DIM);
                    assert!(self.frictions.len() >= SPATIAL_DIM);
                    assert!(self.applied_forces.len() >= SPATIAL_DIM);
                    assert!(self.accelerations.len() >= SPATIAL_DIM);

                    let fixed_joint = MultibodyJoint::fixed(root_pose);
                    let prev_root_ndofs = self.links[0].joint().ndofs();
                    self.links[0].joint = fixed_joint;
                    self.links[0].assembly_id = 0;
                    self.ndofs -= prev_root_ndofs;

                    if self.ndofs == 0 {
                        self.velocities = DVector::zeros(0);
                        self.damping = DVector::zeros(0);
                        self.armature = DVector::zeros(0);
                        self.frictions = DVector::zeros(0);
                        self.applied_forces = DVector::zeros(0);
                        self.accelerations = DVector::zeros(0);
                    } else {
                        self.velocities =
                            self.velocities.index((prev_root_ndofs.., 0)).into_owned();
                        self.damping = self.damping.index((prev_root_ndofs.., 0)).into_owned();
                        self.armature = self.armature.index((prev_root_ndofs.., 0)).into_owned();
                        self.frictions = self.frictions.index((prev_root_ndofs.., 0)).into_owned();
                        self.applied_forces = self
                            .applied_forces
                            .index((prev_root_ndofs.., 0))
                            .into_owned();
                        self.accelerations = self
                            .accelerations
                            .index((prev_root_ndofs.., 0))
                            .into_owned();
                    }

                    for link in &mut self.links[1..] {
                        link.assembly_id -= prev_root_ndofs;
                    }
                }

                self.root_is_dynamic = rb.is_dynamic();
            }

            // Make sure the positions are properly set to match the rigid-body’s.
            if take_body_pose {
                if self.links[0].joint.data.locked_axes.is_empty() {
                    self.links[0].joint.set_free_pos(*rb.position());
                } else {
                    self.links[0].joint.data.local_frame1 = *rb.position();
                }
            }
        }
    }

    /// Update the rigid-body poses based on this multibody joint poses.
    ///
    /// This is typically called after [`Self::forward_kinematics`] to apply the new joint poses
    /// to the rigid-bodies.
    pub fn update_rigid_bodies(&self, bodies: &mut RigidBodySet, update_mass_properties: bool) {
        self.update_rigid_bodies_internal(bodies, update_mass_properties, false, true)
    }

    pub(crate) fn update_rigid_bodies_internal(
        &self,
        bodies: &mut RigidBodySet,
        update_mass_properties: bool,
        update_next_positions_only: bool,
        change_tracking: bool,
    ) {
        // Handle the children. They all have a parent within this multibody.
        for link in self.links.iter() {
            let rb = if change_tracking {
                bodies.get_mut_internal_with_modification_tracking(link.rigid_body)
            } else {
                bodies.get_mut_internal(link.rigid_body)
            };

            if let Some(rb) = rb {
                rb.pos.next_position = link.local_to_world;

                if !update_next_positions_only {
                    rb.pos.position = link.local_to_world;
                }

                if update_mass_properties {
                    rb.mprops
                        .update_world_mass_properties(rb.body_type, &link.local_to_world);
                }
            }
        }
    }

    // TODO: make a version that doesn’t write back to bodies and doesn’t update the jacobians
    //       (i.e. just something used by the velocity solver’s small steps).
    /// Apply forward-kinematics to this multibody.
    ///
    /// This will update the [`MultibodyLink`] pose information as wall as the body jacobians.
    /// This will also ensure that the multibody has the proper number of degrees of freedom if
    /// its root node changed between dynamic and non-dynamic.
    ///
    /// Note that this does **not** update the poses of the [`RigidBody`] attached to the joints.
    /// Run [`Self::update_rigid_bodies`] to trigger that update.
    ///
    /// This method updates `self` with the result of the forward-kinematics operation.
    /// For a non-mutable version running forward kinematics on a single link, see
    /// [`Self::forward_kinematics_single_link`].
    ///
    /// ## Parameters
    /// - `bodies`: the set of rigid-bodies.
    /// - `read_root_pose_from_rigid_body`: if set to `true`, the root joint (either a fixed joint,
    ///   or a free joint) will have its pose set to its associated-rigid-body pose. Set this to `true`
    ///   when the root rigid-body pose has been modified and needs to affect the multibody.
    pub fn forward_kinematics(
        &mut self,
        bodies: &RigidBodySet,
        read_root_pose_from_rigid_body: bool,
    ) {
        self.update_link_poses(bodies, read_root_pose_from_rigid_body);
        self.update_body_jacobians();
    }

    /// The solver's forward kinematics between two substeps (gymfleet patch 33, see
    /// `PATCHES.md`): the links' poses and shifts, and in 3D only each link's own columns of
    /// its body jacobian, all that the next substep's dynamics read (the composite pass and
    /// `update_acceleration`). The solver uses it only when nothing else reads the body
    /// jacobians before the next full [`Multibody::forward_kinematics`] (no impulse joint in
    /// the island; the contacts' jacobians are built once per step); the link-by-link
    /// mass-matrix construction completes them itself.
    pub(crate) fn forward_kinematics_between_substeps(&mut self, bodies: &RigidBodySet) {
        self.update_link_poses(bodies, false);
        #[cfg(feature = "dim3")]
        self.update_own_body_jacobian_columns();
        #[cfg(feature = "dim2")]
        self.update_body_jacobians();
    }

    /// The links' poses and shifts from the coordinates (the first part of
    /// [`Multibody::forward_kinematics`]).
    fn update_link_poses(&mut self, bodies: &RigidBodySet, read_root_pose_from_rigid_body: bool) {
        // Be sure the degrees of freedom match and take the root position if needed.
        self.update_root_type(bodies, read_root_pose_from_rigid_body);

        // Special case for the root, which has no parent.
        {
            let link = &mut self.links[0];
            link.local_to_parent = link.joint.body_to_parent();
            link.local_to_world = link.local_to_parent;
            link.shift23 = root_shift23(link, bodies);
        }

        // Handle the children. They all have a parent within this multibody.
        for i in 1..self.links.len() {
            let (link, parent_link) = self.links.get_mut_with_parent(i);

            link.local_to_parent = link.joint.body_to_parent();
            link.local_to_world = parent_link.local_to_world * link.local_to_parent;

            {
                let parent_rb = &bodies[parent_link.rigid_body];
                let link_rb = &bodies[link.rigid_body];
                let c0 = parent_link.local_to_world * parent_rb.mprops.local_mprops.local_com;
                let c2 = link.local_to_world * link.joint.data.local_frame2.translation;
                let c3 = link.local_to_world * link_rb.mprops.local_mprops.local_com;

                link.shift02 = c2 - c0;
                link.shift23 = c3 - c2;
            }

            assert_eq!(
                bodies[link.rigid_body].body_type,
                RigidBodyType::Dynamic,
                "A rigid-body that is not at the root of a multibody must be dynamic."
            );
        }
    }

    /// Computes the ids of all the links between the root and the link identified by `link_id`.
    pub fn kinematic_branch(&self, link_id: usize) -> Vec<usize> {
        let mut branch = vec![]; // Perf: avoid allocation.
        let mut curr_id = Some(link_id);

        while let Some(id) = curr_id {
            branch.push(id);
            curr_id = self.links[id].parent_id();
        }

        branch.reverse();
        branch
    }

    /// Apply forward-kinematics to compute the position of a single link of this multibody.
    ///
    /// If `out_jacobian` is `Some`, this will simultaneously compute the new jacobian of this link.
    /// If `displacement` is `Some`, the generalized position considered during transform propagation
    /// is the sum of the current position of `self` and this `displacement`.
    // TODO: this shares a lot of code with `forward_kinematics` and `update_body_jacobians`, except
    //       that we are only traversing a single kinematic chain. Could this be refactored?
    pub fn forward_kinematics_single_link(
        &self,
        bodies: &RigidBodySet,
        link_id: usize,
        displacement: Option<&[Real]>,
        out_jacobian: Option<&mut Jacobian<Real>>,
    ) -> Pose {
        let branch = self.kinematic_branch(link_id);
        self.forward_kinematics_single_branch(bodies, &branch, displacement, out_jacobian)
    }

    /// Apply forward-kinematics to compute the position of a single sorted branch of this multibody.
    ///
    /// The given `branch` must have the following properties:
    /// - It must be sorted, i.e., `branch[i] < branch[i + 1]`.
    /// - All the indices must be part of the same kinematic branch.
    /// - If a link is `branch[i]`, then `branch[i - 1]` must be its parent.
    ///
    /// In general, this method shouldn’t be used directly and [`Self::forward_kinematics_single_link`]
    /// should be preferred since it computes the branch indices automatically.
    ///
    /// If you want to calculate the branch indices manually, see [`Self::kinematic_branch`].
    ///
    /// If `out_jacobian` is `Some`, this will simultaneously compute the new jacobian of this branch.
    /// This represents the body jacobian for the last link in the branch.
    ///
    /// If `displacement` is `Some`, the generalized position considered during transform propagation
    /// is the sum of the current position of `self` and this `displacement`.
    // TODO: this shares a lot of code with `forward_kinematics` and `update_body_jacobians`, except
    //       that we are only traversing a single kinematic chain. Could this be refactored?
    #[profiling::function]
    pub fn forward_kinematics_single_branch(
        &self,
        bodies: &RigidBodySet,
        branch: &[usize],
        displacement: Option<&[Real]>,
        mut out_jacobian: Option<&mut Jacobian<Real>>,
    ) -> Pose {
        if let Some(out_jacobian) = out_jacobian.as_deref_mut() {
            if out_jacobian.ncols() != self.ndofs {
                *out_jacobian = Jacobian::zeros(self.ndofs);
            } else {
                out_jacobian.fill(0.0);
            }
        }

        let mut parent_link: Option<MultibodyLink> = None;

        for i in branch {
            let mut link = self.links[*i];

            if let Some(displacement) = displacement {
                link.joint
                    .apply_displacement(&displacement[link.assembly_id..]);
            }

            let parent_to_world;

            if let Some(parent_link) = parent_link {
                link.local_to_parent = link.joint.body_to_parent();
                link.local_to_world = parent_link.local_to_world * link.local_to_parent;

                {
                    let parent_rb = &bodies[parent_link.rigid_body];
                    let link_rb = &bodies[link.rigid_body];
                    let c0 = parent_link.local_to_world * parent_rb.mprops.local_mprops.local_com;
                    let c2 = link.local_to_world
                        * Vector::from(link.joint.data.local_frame2.translation);
                    let c3 = link.local_to_world * link_rb.mprops.local_mprops.local_com;

                    link.shift02 = c2 - c0;
                    link.shift23 = c3 - c2;
                }

                parent_to_world = parent_link.local_to_world;

                if let Some(out_jacobian) = out_jacobian.as_deref_mut() {
                    let (mut link_j_v, parent_j_w) =
                        out_jacobian.rows_range_pair_mut(0..DIM, DIM..DIM + ANG_DIM);
                    let shift_tr = vect_to_na(link.shift02).gcross_matrix_tr();
                    link_j_v.gemm(1.0, &shift_tr, &parent_j_w, 1.0);
                }
            } else {
                link.local_to_parent = link.joint.body_to_parent();
                link.local_to_world = link.local_to_parent;
                link.shift23 = root_shift23(&link, bodies);
                parent_to_world = Pose::IDENTITY;
            }

            if let Some(out_jacobian) = out_jacobian.as_deref_mut() {
                let ndofs = link.joint.ndofs();
                let mut tmp = SMatrix::<Real, SPATIAL_DIM, SPATIAL_DIM>::zeros();
                let mut link_joint_j = tmp.columns_mut(0, ndofs);
                let mut link_j_part = out_jacobian.columns_mut(link.assembly_id, ndofs);
                link.joint.jacobian(
                    &(parent_to_world.rotation * link.joint.data.local_frame1.rotation),
                    &mut link_joint_j,
                );
                link_j_part += link_joint_j;

                {
                    let (mut link_j_v, link_j_w) =
                        out_jacobian.rows_range_pair_mut(0..DIM, DIM..DIM + ANG_DIM);
                    let shift_tr = vect_to_na(link.shift23).gcross_matrix_tr();
                    link_j_v.gemm(1.0, &shift_tr, &link_j_w, 1.0);
                }
            }

            parent_link = Some(link);
        }

        parent_link
            .map(|link| link.local_to_world)
            .unwrap_or(Pose::IDENTITY)
    }

    /// The total number of freedoms of this multibody.
    #[inline]
    pub fn ndofs(&self) -> usize {
        self.ndofs
    }

    pub(crate) fn fill_jacobians(
        &self,
        link_id: usize,
        unit_force: Vector,
        unit_torque: AngVector,
        j_id: &mut usize,
        jacobians: &mut DVector,
    ) -> (Real, Real) {
        if self.ndofs == 0 {
            return (0.0, 0.0);
        }

        let wj_id = *j_id + self.ndofs;
        let force = Force {
            linear: unit_force,
            #[cfg(feature = "dim2")]
            angular: unit_torque,
            #[cfg(feature = "dim3")]
            angular: unit_torque,
        };

        self.debug_assert_whole_body_jacobians();
        let link = &self.links[link_id];
        let mut out_j = jacobians.rows_mut(*j_id, self.ndofs);
        self.body_jacobians[link.internal_id].tr_mul_to(force.as_vector(), &mut out_j);

        // TODO: Optimize with a copy_nonoverlapping?
        for i in 0..self.ndofs {
            jacobians[wj_id + i] = jacobians[*j_id + i];
        }

        {
            let mut out_invm_j = jacobians.rows_mut(wj_id, self.ndofs);
            self.augmented_mass_indices
                .with_rearranged_rows_mut(&mut out_invm_j, |out_invm_j| {
                    self.inv_augmented_mass().solve_mut(out_invm_j);
                });
        }

        let j = jacobians.rows(*j_id, self.ndofs);
        let invm_j = jacobians.rows(wj_id, self.ndofs);
        *j_id += self.ndofs * 2;

        (j.dot(&invm_j), j.dot(&self.generalized_velocity()))
    }

    /// Fills `jacobians` with the relative jacobian `J = J2ᵀ·f2 − J1ᵀ·f1` of two links of `self`, then `M⁻¹·J`
    /// (e.g. a loop closure). The difference must be explicit: per-link blocks lose the `J1ᵀ·W·J2` effective-mass
    /// coupling since both act on the same generalized velocities. Cancellation-vanished rows are zeroed so the solver skips them.
    pub(crate) fn fill_relative_jacobians(
        &self,
        link_id1: usize,
        unit_force1: Vector,
        unit_torque1: AngVector,
        link_id2: usize,
        unit_force2: Vector,
        unit_torque2: AngVector,
        j_id: &mut usize,
        jacobians: &mut DVector,
    ) {
        if self.ndofs == 0 {
            return;
        }
        self.debug_assert_whole_body_jacobians();

        let wj_id = *j_id + self.ndofs;
        let force1 = Force {
            linear: unit_force1,
            angular: unit_torque1,
        };
        let force2 = Force {
            linear: unit_force2,
            angular: unit_torque2,
        };

        let link1 = &self.links[link_id1];
        let link2 = &self.links[link_id2];

        {
            let jb1 = &self.body_jacobians[link1.internal_id];
            let jb2 = &self.body_jacobians[link2.internal_id];

            // Use the (overwritten below) W·J slot as workspace for J1ᵀ·f1.
            let (mut out_j, mut workspace) =
                jacobians.rows_range_pair_mut(*j_id..*j_id + self.ndofs, wj_id..wj_id + self.ndofs);
            jb2.tr_mul_to(force2.as_vector(), &mut out_j);
            jb1.tr_mul_to(force1.as_vector(), &mut workspace);
            out_j.axpy(-1.0, &workspace, 1.0);

            // Cancellation guard: the reference scale is the magnitude of the dot-product operands,
            // not their results (which may be pure cancellation noise when the direction isn’t
            // expressible by the dofs). Rows below ~1000·ε times that scale are noise, not a constraint.
            let scale_sq = jb1.norm_squared() * force1.as_vector().norm_squared()
                + jb2.norm_squared() * force2.as_vector().norm_squared();
            let eps = Real::EPSILON * 1.0e3;
            if out_j.norm_squared() <= eps * eps * scale_sq {
                out_j.fill(0.0);
            }
        }

        // TODO: Optimize with a copy_nonoverlapping?
        for i in 0..self.ndofs {
            jacobians[wj_id + i] = jacobians[*j_id + i];
        }

        {
            let mut out_invm_j = jacobians.rows_mut(wj_id, self.ndofs);
            self.augmented_mass_indices
                .with_rearranged_rows_mut(&mut out_invm_j, |out_invm_j| {
                    self.inv_augmented_mass().solve_mut(out_invm_j);
                });
        }

        *j_id += self.ndofs * 2;
    }
}

#[cfg_attr(feature = "serde-serialize", derive(Serialize, Deserialize))]
#[derive(Clone, Debug)]
struct IndexSequence {
    first_to_remove: u32,
    index_map: Vec<usize>,
}

impl IndexSequence {
    const NONE: u32 = u32::MAX;

    fn new() -> Self {
        Self {
            first_to_remove: Self::NONE,
            index_map: vec![],
        }
    }

    /// Index of the first removed dof, assuming there is one.
    fn start(&self) -> usize {
        self.first_to_remove as usize
    }

    fn clear(&mut self) {
        self.first_to_remove = Self::NONE;
        self.index_map.clear();
    }

    fn keep(&mut self, i: usize) {
        if self.first_to_remove == Self::NONE {
            // Nothing got removed yet. No need to register any
            // special indexing.
            return;
        }

        self.index_map.push(i);
    }

    fn remove(&mut self, i: usize) {
        if self.first_to_remove == Self::NONE {
            self.first_to_remove = i as u32;
        }
    }

    fn dim_after_removal(&self, original_dim: usize) -> usize {
        if self.first_to_remove == Self::NONE {
            original_dim
        } else {
            self.start() + self.index_map.len()
        }
    }

    fn rearrange_columns<R: na::Dim, C: na::Dim, S: StorageMut<Real, R, C>>(
        &self,
        mat: &mut na::Matrix<Real, R, C, S>,
        clear_removed: bool,
    ) {
        if self.first_to_remove == Self::NONE {
            // Nothing to rearrange.
            return;
        }

        for (target_shift, source) in self.index_map.iter().enumerate() {
            let target = self.start() + target_shift;
            let (mut target_col, source_col) = mat.columns_range_pair_mut(target, *source);
            target_col.copy_from(&source_col);
        }

        if clear_removed {
            mat.columns_range_mut(self.start() + self.index_map.len()..)
                .fill(0.0);
        }
    }

    fn rearrange_rows<R: na::Dim, C: na::Dim, S: StorageMut<Real, R, C>>(
        &self,
        mat: &mut na::Matrix<Real, R, C, S>,
        clear_removed: bool,
    ) {
        if self.first_to_remove == Self::NONE {
            // Nothing to rearrange.
            return;
        }

        for mut col in mat.column_iter_mut() {
            for (target_shift, source) in self.index_map.iter().enumerate() {
                let target = self.start() + target_shift;
                col[target] = col[*source];
            }

            if clear_removed {
                col.rows_range_mut(self.start() + self.index_map.len()..)
                    .fill(0.0);
            }
        }
    }

    fn inv_rearrange_rows<R: na::Dim, C: na::Dim, S: StorageMut<Real, R, C>>(
        &self,
        mat: &mut na::Matrix<Real, R, C, S>,
    ) {
        if self.first_to_remove == Self::NONE {
            // Nothing to rearrange.
            return;
        }

        for mut col in mat.column_iter_mut() {
            for (target_shift, source) in self.index_map.iter().enumerate().rev() {
                let target = self.start() + target_shift;
                col[*source] = col[target];
                col[target] = 0.0;
            }
        }
    }

    fn with_rearranged_rows_mut<C: na::Dim, S: StorageMut<Real, Dyn, C>>(
        &self,
        mat: &mut na::Matrix<Real, Dyn, C, S>,
        mut f: impl FnMut(&mut na::MatrixViewMut<Real, Dyn, C, S::RStride, S::CStride>),
    ) {
        self.rearrange_rows(mat, true);
        let effective_dim = self.dim_after_removal(mat.nrows());
        if effective_dim > 0 {
            f(&mut mat.rows_mut(0, effective_dim));
        }
        self.inv_rearrange_rows(mat);
    }
}

#[cfg(test)]
mod test {
    use super::IndexSequence;
    use crate::alloc_prelude::*;
    use crate::dynamics::{ImpulseJointSet, IslandManager};
    #[cfg(feature = "dim3")]
    use crate::math::Vector;
    use crate::math::{Real, SPATIAL_DIM};
    use crate::prelude::{
        ColliderSet, MultibodyJointHandle, MultibodyJointSet, RevoluteJoint, RigidBodyBuilder,
        RigidBodySet, SoftBodySet,
    };
    use na::{DVector, RowDVector};

    #[test]
    fn test_multibody_append() {
        let mut bodies = RigidBodySet::new();
        let mut joints = MultibodyJointSet::new();

        let a = bodies.insert(RigidBodyBuilder::dynamic());
        let b = bodies.insert(RigidBodyBuilder::dynamic());
        let c = bodies.insert(RigidBodyBuilder::dynamic());
        let d = bodies.insert(RigidBodyBuilder::dynamic());

        #[cfg(feature = "dim2")]
        let joint = RevoluteJoint::new();
        #[cfg(feature = "dim3")]
        let joint = RevoluteJoint::new(Vector::X);

        let mb_handle = joints.insert(a, b, joint, true).unwrap();
        joints.insert(c, d, joint, true).unwrap();
        joints.insert(b, c, joint, true).unwrap();

        assert_eq!(joints.get(mb_handle).unwrap().0.ndofs, SPATIAL_DIM + 3);
    }

    #[test]
    fn test_multibody_insert() {
        let mut rnd = oorandom::Rand32::new(1234);

        for k in 0..10 {
            let mut bodies = RigidBodySet::new();
            let mut multibody_joints = MultibodyJointSet::new();

            let num_links = 100;
            let mut handles = vec![];

            for _ in 0..num_links {
                handles.push(bodies.insert(RigidBodyBuilder::dynamic()));
            }

            let mut insertion_id: Vec<_> = (0..num_links - 1).collect();

            #[cfg(feature = "dim2")]
            let joint = RevoluteJoint::new();
            #[cfg(feature = "dim3")]
            let joint = RevoluteJoint::new(Vector::X);

            match k {
                0 => {} // Remove in insertion order.
                1 => {
                    // Remove from leaf to root.
                    insertion_id.reverse();
                }
                _ => {
                    // Shuffle the vector a bit.
                    // (This test checks multiple shuffle arrangements due to k > 2).
                    for l in 0..num_links - 1 {
                        insertion_id.swap(l, rnd.rand_range(0..num_links as u32 - 1) as usize);
                    }
                }
            }

            let mut mb_handle = MultibodyJointHandle::invalid();
            for i in insertion_id {
                mb_handle = multibody_joints
                    .insert(handles[i], handles[i + 1], joint, true)
                    .unwrap();
            }

            assert_eq!(
                multibody_joints.get(mb_handle).unwrap().0.ndofs,
                SPATIAL_DIM + num_links - 1
            );
        }
    }

    #[test]
    fn test_multibody_remove() {
        let mut rnd = oorandom::Rand32::new(1234);

        for k in 0..10 {
            let mut bodies = RigidBodySet::new();
            let mut multibody_joints = MultibodyJointSet::new();
            let mut colliders = ColliderSet::new();
            let mut impulse_joints = ImpulseJointSet::new();
            let mut islands = IslandManager::new();
            let mut soft_bodies = SoftBodySet::new();

            let num_links = 100;
            let mut handles = vec![];

            for _ in 0..num_links {
                handles.push(bodies.insert(RigidBodyBuilder::dynamic()));
            }

            #[cfg(feature = "dim2")]
            let joint = RevoluteJoint::new();
            #[cfg(feature = "dim3")]
            let joint = RevoluteJoint::new(Vector::X);

            for i in 0..num_links - 1 {
                multibody_joints
                    .insert(handles[i], handles[i + 1], joint, true)
                    .unwrap();
            }

            match k {
                0 => {} // Remove in insertion order.
                1 => {
                    // Remove from leaf to root.
                    handles.reverse();
                }
                _ => {
                    // Shuffle the vector a bit.
                    // (This test checks multiple shuffle arrangements due to k > 2).
                    for l in 0..num_links {
                        handles.swap(l, rnd.rand_range(0..num_links as u32) as usize);
                    }
                }
            }

            for handle in handles {
                bodies.remove(
                    handle,
                    &mut islands,
                    &mut colliders,
                    &mut impulse_joints,
                    &mut multibody_joints,
                    &mut soft_bodies,
                    true,
                );
            }
        }
    }

    fn test_sequence() -> IndexSequence {
        let mut seq = IndexSequence::new();
        seq.remove(2);
        seq.remove(3);
        seq.remove(4);
        seq.keep(5);
        seq.keep(6);
        seq.remove(7);
        seq.keep(8);
        seq
    }

    #[test]
    fn index_sequence_rearrange_columns() {
        let seq = test_sequence();
        let mut vec = RowDVector::from_fn(10, |_, c| c as Real);
        seq.rearrange_columns(&mut vec, true);
        assert_eq!(
            vec,
            RowDVector::from(vec![0.0, 1.0, 5.0, 6.0, 8.0, 0.0, 0.0, 0.0, 0.0, 0.0])
        );
    }

    #[test]
    fn index_sequence_rearrange_rows() {
        let seq = test_sequence();
        let mut vec = DVector::from_fn(10, |r, _| r as Real);
        seq.rearrange_rows(&mut vec, true);
        assert_eq!(
            vec,
            DVector::from(vec![0.0, 1.0, 5.0, 6.0, 8.0, 0.0, 0.0, 0.0, 0.0, 0.0])
        );
        seq.inv_rearrange_rows(&mut vec);
        assert_eq!(
            vec,
            DVector::from(vec![0.0, 1.0, 0.0, 0.0, 0.0, 5.0, 6.0, 0.0, 8.0, 0.0])
        );
    }

    #[test]
    fn index_sequence_with_rearranged_rows_mut() {
        let seq = test_sequence();
        let mut vec = DVector::from_fn(10, |r, _| r as Real);
        seq.with_rearranged_rows_mut(&mut vec, |v| {
            assert_eq!(v.len(), 5);
            assert_eq!(*v, DVector::from(vec![0.0, 1.0, 5.0, 6.0, 8.0]));
            *v *= 10.0;
        });
        assert_eq!(
            vec,
            DVector::from(vec![0.0, 10.0, 0.0, 0.0, 0.0, 50.0, 60.0, 0.0, 80.0, 0.0])
        );
    }
}

/// gymfleet patch 15 (`PATCHES.md`): a still multibody's mass matrix leaves out the velocity
/// terms; these tests pin that they are negligible there and matter elsewhere.
#[cfg(all(test, feature = "dim3"))]
mod still_multibody_tests {
    use super::{Multibody, NEGLIGIBLE_MOTION_PER_SUBSTEP};
    use crate::math::{DVector, Real, Vector};
    use crate::prelude::*;

    const DT: Real = 1.0 / 1200.0;

    /// A fixed base and three links on revolute joints about Z, X and Z (general enough for
    /// every coriolis and gyroscopic term to be non-zero once the chain moves).
    fn chain() -> (PhysicsWorld, MultibodyJointHandle) {
        let mut world = PhysicsWorld::new();
        let mut parent = world.insert_body(RigidBodyBuilder::fixed());
        let mut joint = None;
        for (i, axis) in [Vector::Z, Vector::X, Vector::Z].into_iter().enumerate() {
            let (link, _) = world.insert(
                RigidBodyBuilder::dynamic()
                    .translation(Vector::new(0.3 * (i + 1) as Real, 0.05, 0.0)),
                ColliderBuilder::capsule_x(0.1, 0.02).translation(Vector::new(0.1, 0.0, 0.0)),
            );
            let anchor = if i == 0 { Vector::ZERO } else { Vector::new(0.3, 0.05, 0.0) };
            let rev = RevoluteJointBuilder::new(axis).local_anchor1(anchor);
            joint = world.insert_multibody_joint(parent, link, rev);
            parent = link;
        }
        (world, joint.unwrap())
    }

    /// gymfleet patch 50: without contacts or limits the damping order changes nothing: a
    /// damped chain swinging under gravity takes the same path (to `f32` rounding) with the
    /// damping after the constraints as with it in the matrix, and the order is in force.
    #[test]
    fn the_damping_after_the_constraints_leaves_free_motion_as_it_is() {
        let run = |after: bool| {
            let (mut world, joint) = chain();
            world.integration_parameters.num_solver_iterations = 1;
            world.gravity = Vector::new(0.0, -9.81, 0.0);
            let mb = multibody(&mut world, joint);
            mb.set_self_contacts_enabled(false);
            mb.damping_mut().fill(0.01);
            mb.set_damping_after_constraints(after);
            for (i, v) in mb.velocities.iter_mut().enumerate() {
                *v = [3.0, -2.0, 4.0][i % 3];
            }
            for _ in 0..12 {
                world.step();
            }
            let mb = multibody(&mut world, joint);
            (mb.velocities.clone(), mb.damping_after_active.is_some())
        };
        let ((before, off), (after, on)) = (run(false), run(true));
        assert!(!off && on, "the order is in force only when asked for");
        assert!(before.amax() > 0.1, "the chain swings: {before:?}");
        let gap = (&before - &after).amax() / before.amax();
        assert!(gap < 1.0e-5, "{before:?} against {after:?}: {gap}");
    }

    /// Sets the chain's generalized velocities and updates its dynamics at them.
    fn update_at(world: &mut PhysicsWorld, joint: MultibodyJointHandle, velocities: &[Real]) {
        let mb = world.multibody_joints.get_mut(joint).unwrap().0;
        mb.forward_kinematics(&world.bodies, false);
        mb.velocities.copy_from_slice(velocities);
        mb.update_velocities(&mut world.bodies);
        mb.update_mass_matrix(DT, &world.bodies);
    }

    fn multibody(world: &mut PhysicsWorld, joint: MultibodyJointHandle) -> &mut Multibody {
        world.multibody_joints.get_mut(joint).unwrap().0
    }

    /// `max |acc_augmented_mass − augmented_mass| / max |augmented_mass|`.
    fn velocity_terms_share(mb: &Multibody) -> Real {
        (&mb.acc_augmented_mass - &mb.augmented_mass).amax() / mb.augmented_mass.amax()
    }

    #[test]
    fn a_still_multibody_leaves_out_the_velocity_terms_and_factorizes_once() {
        let (mut world, joint) = chain();
        update_at(&mut world, joint, &[1.0e-13, -2.0e-13, 1.0e-13]);
        let mb = multibody(&mut world, joint);
        assert!(mb.velocity_terms_skipped);
        assert_eq!(mb.acc_augmented_mass, mb.augmented_mass);

        // The plain matrix's factorization, copied from the semi-implicit one, solves
        // exactly as its own factorization does.
        mb.factorize_inv_augmented_mass();
        let mut fresh = super::MassMatrixLu::default();
        fresh.factorize_symmetric_leading(&mb.augmented_mass, mb.augmented_mass.nrows());
        let mut copied_x = DVector::from_row_slice(&[0.3, -1.0, 2.0]);
        let mut fresh_x = copied_x.clone();
        assert!(mb.inv_augmented_mass().solve_mut(&mut copied_x));
        assert!(fresh.solve_mut(&mut fresh_x));
        assert_eq!(copied_x, fresh_x);
    }

    #[test]
    fn the_velocity_terms_at_the_threshold_are_far_below_f32_resolution() {
        let (mut world, joint) = chain();
        // Just above the threshold: computed, and they change the matrix by ~1e-12 of itself.
        let speed = 1.01 * NEGLIGIBLE_MOTION_PER_SUBSTEP / DT;
        update_at(&mut world, joint, &[speed, -speed, speed]);
        let mb = multibody(&mut world, joint);
        assert!(!mb.velocity_terms_skipped);
        let share = velocity_terms_share(mb);
        assert!(share < 1.0e-10, "velocity terms at the threshold: {share:e} of the matrix");

        // At a real speed they matter (so the share above measures something).
        update_at(&mut world, joint, &[2.0, -3.0, 4.0]);
        let mb = multibody(&mut world, joint);
        assert!(!mb.velocity_terms_skipped);
        let share = velocity_terms_share(mb);
        assert!(share > 1.0e-4, "velocity terms at 2-4 rad/s: {share:e} of the matrix");
    }

    /// gymfleet patch 26: explicit velocity terms leave the derivative out at any speed, and
    /// the accelerations solve the plain mass matrix against the very forces the
    /// semi-implicit step solves `M + dt·D` against.
    #[test]
    fn explicit_velocity_terms_solve_the_same_forces_with_the_plain_matrix() {
        let speeds = [2.0, -3.0, 4.0];
        let (mut world, joint) = chain();
        assert!(!multibody(&mut world, joint).explicit_velocity_terms());
        update_at(&mut world, joint, &speeds);
        let mb = world.multibody_joints.get_mut(joint).unwrap().0;
        assert!(!mb.velocity_terms_skipped);
        assert!(velocity_terms_share(mb) > 1.0e-4);
        mb.update_acceleration(DT, &world.bodies);
        // The generalized forces, as the energy guard keeps them.
        let forces = mb.workspace.gen_forces.clone();
        assert_eq!(
            forces.len(),
            3,
            "the forces were not kept: the test tells nothing"
        );

        multibody(&mut world, joint).set_explicit_velocity_terms(true);
        update_at(&mut world, joint, &speeds);
        let mb = world.multibody_joints.get_mut(joint).unwrap().0;
        assert!(mb.velocity_terms_skipped);
        assert_eq!(mb.acc_augmented_mass, mb.augmented_mass);
        mb.update_acceleration(DT, &world.bodies);
        let residual = (&mb.augmented_mass * &mb.accelerations - &forces).amax() / forces.amax();
        assert!(
            residual < 1.0e-5,
            "explicit: M·a misses the forces by {residual:e}"
        );
    }

    /// gymfleet patch 27: with the velocity terms left out, the energy guard does not run
    /// (its fallback would solve the same matrix with the same factors): the accelerations
    /// are the bits of one solve of the plain matrix, and non-finite ones are still cleared.
    #[test]
    fn without_velocity_terms_the_energy_guard_is_skipped_and_changes_no_bit() {
        let speeds = [2.0, -3.0, 4.0];
        let (mut world, joint) = chain();
        update_at(&mut world, joint, &speeds);
        let mb = world.multibody_joints.get_mut(joint).unwrap().0;
        mb.update_acceleration(DT, &world.bodies);
        let forces = mb.workspace.gen_forces.clone();
        assert_eq!(forces.len(), 3, "the guard did not run at 2-4 rad/s");

        multibody(&mut world, joint).set_explicit_velocity_terms(true);
        update_at(&mut world, joint, &speeds);
        let mb = world.multibody_joints.get_mut(joint).unwrap().0;
        mb.workspace.gen_forces = DVector::zeros(0);
        mb.update_acceleration(DT, &world.bodies);
        assert_eq!(mb.workspace.gen_forces.len(), 0, "the guard ran");
        // What the guard's fallback computes: the plain matrix factorized, the forces solved.
        let mut fresh = super::MassMatrixLu::default();
        fresh.factorize_symmetric_leading(&mb.augmented_mass, mb.augmented_mass.nrows());
        let mut expected = forces.clone();
        assert!(fresh.solve_mut(&mut expected));
        assert_eq!(mb.accelerations, expected);

        // A non-finite force: the accelerations are cleared, as the guard's last chance did.
        mb.applied_forces_mut()[1] = Real::NAN;
        mb.update_acceleration(DT, &world.bodies);
        assert!(
            mb.accelerations.iter().all(|a| *a == 0.0),
            "{}",
            mb.accelerations
        );
    }

    #[test]
    fn a_spinning_free_root_keeps_the_velocity_terms() {
        let (mut world, joint) = chain();
        let root = multibody(&mut world, joint).links[0].rigid_body;
        world
            .bodies
            .get_mut(root)
            .unwrap()
            .set_body_type(RigidBodyType::Dynamic, true);
        // The free root's six DoFs come first; spin it about Y, the joints still.
        let mb = world.multibody_joints.get_mut(joint).unwrap().0;
        mb.forward_kinematics(&world.bodies, false);
        update_at(&mut world, joint, &[0.0, 0.0, 0.0, 0.0, 3.0, 0.0, 0.0, 0.0, 0.0]);
        let mb = multibody(&mut world, joint);
        assert!(!mb.velocity_terms_skipped);
        assert!(velocity_terms_share(mb) > 1.0e-4);
    }
}

/// gymfleet patch 16 (`PATCHES.md`): the composite-rigid-body construction of both mass
/// matrices gives the link-by-link construction's matrices.
#[cfg(all(test, feature = "dim3"))]
mod composite_tests {
    use super::Multibody;
    use crate::math::{DMatrix, DVector, Real, Vector};
    use crate::prelude::*;

    const DT: Real = 1.0 / 1200.0;

    /// A tree: revolute Z, prismatic X, revolute Y on one branch, then a welded link and a
    /// revolute about a skew axis; a revolute X on a second branch. Every link's centre of
    /// mass is off its joint and the joints start displaced and moving. On a fixed base or, with `free_root`, on a free (dynamic) base whose centre of mass is
    /// off its origin, moving and turned (six more DoFs, first).
    fn tree_on(free_root: bool) -> (PhysicsWorld, MultibodyJointHandle) {
        let mut world = PhysicsWorld::new();
        let base = if free_root {
            world
                .insert(
                    RigidBodyBuilder::dynamic().translation(Vector::new(0.2, 1.0, -0.1)),
                    ColliderBuilder::cuboid(0.1, 0.05, 0.08)
                        .translation(Vector::new(0.03, -0.02, 0.04))
                        .density(900.0),
                )
                .0
        } else {
            world.insert_body(RigidBodyBuilder::fixed().translation(Vector::new(0.2, 1.0, -0.1)))
        };
        let link = |world: &mut PhysicsWorld, at: Vector, half: Vector| {
            world
                .insert(
                    RigidBodyBuilder::dynamic().translation(at),
                    ColliderBuilder::cuboid(half.x, half.y, half.z)
                        .translation(Vector::new(half.x, 0.02, -0.01))
                        .density(700.0 + 100.0 * at.x),
                )
                .0
        };
        let l1 = link(&mut world, Vector::new(0.2, 1.0, -0.1), Vector::new(0.15, 0.03, 0.02));
        let l2 = link(&mut world, Vector::new(0.5, 1.0, -0.1), Vector::new(0.1, 0.02, 0.04));
        let l3 = link(&mut world, Vector::new(0.7, 1.0, -0.1), Vector::new(0.12, 0.03, 0.03));
        let l4 = link(&mut world, Vector::new(0.2, 1.1, -0.1), Vector::new(0.08, 0.05, 0.02));
        let l5 = link(&mut world, Vector::new(0.94, 1.0, -0.1), Vector::new(0.05, 0.02, 0.02));
        let l6 = link(&mut world, Vector::new(1.04, 1.0, -0.1), Vector::new(0.09, 0.02, 0.03));
        let skew = Vector::new(1.0, 1.0, 0.0).normalize();
        let joints: [(RigidBodyHandle, RigidBodyHandle, GenericJoint, Vector); 6] = [
            (base, l1, RevoluteJointBuilder::new(Vector::Z).into(), Vector::ZERO),
            (l1, l2, PrismaticJointBuilder::new(Vector::X).into(), Vector::new(0.3, 0.0, 0.0)),
            (l2, l3, RevoluteJointBuilder::new(Vector::Y).into(), Vector::new(0.2, 0.0, 0.0)),
            (l1, l4, RevoluteJointBuilder::new(Vector::X).into(), Vector::new(0.0, 0.1, 0.0)),
            (l3, l5, FixedJointBuilder::new().into(), Vector::new(0.24, 0.0, 0.0)),
            (l5, l6, RevoluteJointBuilder::new(skew).into(), Vector::new(0.1, 0.0, 0.0)),
        ];
        let mut handle = None;
        for (parent, child, mut joint, anchor) in joints {
            joint.set_local_anchor1(anchor);
            handle = world.insert_multibody_joint(parent, child, joint);
        }
        let handle = handle.unwrap();
        let mb = world.multibody_joints.get_mut(handle).unwrap().0;
        // A fixed root collapses from a free joint to a fixed one here.
        mb.forward_kinematics(&world.bodies, false);
        let joints = [0.4, 0.05, -0.6, 0.9, 0.3];
        let joint_velocities = [1.3, -0.7, 2.1, 0.4, -1.9];
        if free_root {
            assert_eq!(mb.ndofs(), 11);
            let root = [0.1, -0.2, 0.05, 0.3, -0.5, 0.7];
            mb.apply_displacements(&[&root[..], &joints[..]].concat());
            mb.forward_kinematics(&world.bodies, false);
            mb.update_rigid_bodies(&mut world.bodies, true);
            let root_velocity = [0.8, -0.3, 1.1, -1.4, 0.6, 2.2];
            mb.velocities
                .copy_from_slice(&[&root_velocity[..], &joint_velocities[..]].concat());
        } else {
            assert_eq!(mb.ndofs(), 5);
            mb.apply_displacements(&joints);
            mb.forward_kinematics(&world.bodies, false);
            // World inertias and centres of mass of the displaced links, as the solver keeps them.
            mb.update_rigid_bodies(&mut world.bodies, true);
            mb.velocities.copy_from_slice(&joint_velocities);
        }
        mb.update_velocities(&mut world.bodies);
        mb.update_mass_matrix(DT, &world.bodies);
        (world, handle)
    }

    /// `(M's upper triangle, dt·D)` as built by `build`, from zeroed matrices.
    fn matrices(mb: &mut Multibody, build: impl Fn(&mut Multibody)) -> (DMatrix, DMatrix) {
        mb.augmented_mass.fill(0.0);
        mb.acc_augmented_mass.fill(0.0);
        build(mb);
        let mut mass = mb.augmented_mass.clone();
        for b in 0..mass.ncols() {
            for a in b + 1..mass.nrows() {
                mass[(a, b)] = 0.0;
            }
        }
        (mass, mb.acc_augmented_mass.clone())
    }

    /// The generalized forces `update_acceleration` applies at the tree's configuration with
    /// velocities `qdot`: damping and the coriolis, centrifugal and gyroscopic forces (no
    /// gravity or applied force here).
    fn generalized_forces(
        world: &mut PhysicsWorld,
        handle: MultibodyJointHandle,
        qdot: &DVector,
    ) -> DVector {
        let mb = world.multibody_joints.get_mut(handle).unwrap().0;
        mb.velocities.copy_from(qdot);
        mb.update_velocities(&mut world.bodies);
        mb.update_mass_matrix(DT, &world.bodies);
        // Fast enough for the energy guard, which keeps a copy of the forces.
        assert!(DT * qdot.amax() >= 1.0e-3);
        mb.update_acceleration(DT, &world.bodies);
        mb.workspace.gen_forces.clone()
    }

    /// `dt·∂τ/∂q̇` of Rapier's own generalized forces `τ` (less the damping's constant part), by
    /// central differences, which are exact for forces quadratic in the velocities.
    fn velocity_derivative(world: &mut PhysicsWorld, handle: MultibodyJointHandle) -> DMatrix {
        let mb = world.multibody_joints.get(handle).unwrap().0;
        let (qdot, damping, n) = (mb.velocities.clone(), mb.damping.clone(), mb.ndofs());
        let mut derivative = DMatrix::zeros(n, n);
        for c in 0..n {
            let (mut plus, mut minus) = (qdot.clone(), qdot.clone());
            plus[c] += 1.0;
            minus[c] -= 1.0;
            let forces = generalized_forces(world, handle, &plus)
                - generalized_forces(world, handle, &minus);
            for a in 0..n {
                // The forces are −τ − d·q̇.
                let damping = if a == c { damping[a] } else { 0.0 };
                derivative[(a, c)] = DT * (-forces[a] / 2.0 - damping);
            }
        }
        generalized_forces(world, handle, &qdot);
        derivative
    }

    fn relative_error(ours: &DMatrix, reference: &DMatrix) -> Real {
        (ours - reference).amax() / reference.amax()
    }

    #[test]
    fn a_tree_of_one_dof_joints_builds_both_matrices_by_composite_bodies() {
        composite_matches_the_link_by_link_mass_and_the_forces_derivative(false);
    }

    #[test]
    fn a_tree_on_a_free_root_builds_both_matrices_by_composite_bodies() {
        composite_matches_the_link_by_link_mass_and_the_forces_derivative(true);
    }

    fn composite_matches_the_link_by_link_mass_and_the_forces_derivative(free_root: bool) {
        let (mut world, handle) = tree_on(free_root);
        let derivative = velocity_derivative(&mut world, handle);
        let bodies = &world.bodies;
        let mb = world.multibody_joints.get_mut(handle).unwrap().0;
        assert!(mb.composite_applies(bodies, true));
        // `update_mass_matrix` (which `velocity_derivative` left at the tree's velocities)
        // takes this construction: its two matrices differ by exactly `dt·D`.
        let update_velocity = &mb.acc_augmented_mass - &mb.augmented_mass;
        let update_error = relative_error(&update_velocity, &derivative);
        assert!(update_error < 1.0e-5, "update_mass_matrix's dt·D: {update_error:e}");
        let (mass, velocity) = matrices(mb, |mb| mb.composite_mass_matrices(DT, true, bodies));
        let (link_mass, link_velocity) = matrices(mb, |mb| {
            for i in 0..mb.links.len() {
                let span = mb.links[i].assembly_id + mb.links[i].joint.ndofs();
                mb.accumulate_link_mass_3d(i, span, DT, true, bodies);
            }
        });
        // M: the same sums in another order (and in f64 rather than f32).
        let mass_error = relative_error(&mass, &link_mass);
        assert!(mass_error < 1.0e-6, "M: {mass_error:e}\n{mass}\n{link_mass}");
        // dt·D: the derivative of the forces the dynamics apply (measured: 2e-7 off it). The
        // link-by-link construction is not that derivative (27 % of the largest entry off).
        let velocity_error = relative_error(&velocity, &derivative);
        let link_error = relative_error(&link_velocity, &derivative);
        assert!(link_error > 0.1, "the link-by-link velocity terms: {link_error:e}");
        assert!(
            velocity_error < 1.0e-5,
            "dt·D: {velocity_error:e} (link by link: {link_error:e})\n{velocity}\n{derivative}"
        );
        // The velocity terms are not trivially zero, and not symmetric.
        assert!(derivative.amax() > 1.0e-4 * link_mass.amax());
        assert!((&derivative - derivative.transpose()).amax() > 0.1 * derivative.amax());
    }

    /// Kinetic energy and linear momentum of every dynamic body.
    fn energy_and_momentum(world: &PhysicsWorld) -> (Real, Vector) {
        let (mut energy, mut momentum) = (0.0, Vector::ZERO);
        for (_, rb) in world.bodies.iter() {
            let (m, v, w) = (rb.mass(), rb.linvel(), rb.angvel());
            let inertia = rb.mprops.effective_world_inv_inertia.inverse_unchecked();
            energy += 0.5 * (m * v.length_squared() + w.dot(inertia * w));
            momentum += v * m;
        }
        (energy, momentum)
    }

    /// A free tree tumbling without gravity, contacts or damping for 2 s (480 steps): its
    /// linear momentum stays within 0.5 % and its energy never grows; the semi-implicit
    /// velocity terms dissipate some of it, as with the link-by-link construction (measured:
    /// 5.097 → 4.554 here, 5.097 → 4.558 link by link; momentum 0.38 % and 0.33 % off).
    #[test]
    fn a_free_tree_tumbling_without_gravity_keeps_its_momentum_and_gains_no_energy() {
        let (mut world, handle) = tree_on(true);
        world.gravity = Vector::ZERO;
        world.integration_parameters.dt = 1.0 / 240.0;
        world.integration_parameters.num_solver_iterations = 4;
        for (_, collider) in world.colliders.iter_mut() {
            collider.set_collision_groups(InteractionGroups::none());
        }
        world.step();
        let mb = world.multibody_joints.get(handle).unwrap().0;
        assert!(mb.composite_applies(&world.bodies, true));
        let (energy0, momentum0) = energy_and_momentum(&world);
        for _ in 0..480 {
            world.step();
            let (energy, momentum) = energy_and_momentum(&world);
            assert!(energy < energy0 * 1.001 && energy > 0.85 * energy0, "{energy} from {energy0}");
            let drift = (momentum - momentum0).length() / momentum0.length();
            assert!(drift < 0.005, "momentum {momentum:?} from {momentum0:?}");
        }
    }

    /// A planar root (slides along X and Z, a hinge about Y: MJCF's slide/slide/hinge roots as
    /// one joint), a revolute and a ball joint on it, and a cylindrical joint below the ball,
    /// displaced and moving. Without the velocity terms `M` is built by composite bodies, the
    /// same as link by link (gymfleet patch 30); with them the link-by-link construction stays.
    #[test]
    fn joints_of_several_dofs_build_the_mass_matrix_by_composite_bodies_without_velocity_terms() {
        let mut world = PhysicsWorld::new();
        let base =
            world.insert_body(RigidBodyBuilder::fixed().translation(Vector::new(0.0, 0.0, 0.6)));
        let link = |world: &mut PhysicsWorld, at: Vector, half: Vector| {
            world
                .insert(
                    RigidBodyBuilder::dynamic().translation(at),
                    ColliderBuilder::cuboid(half.x, half.y, half.z)
                        .translation(Vector::new(half.x, 0.02, -0.01))
                        .density(700.0 + 100.0 * at.x),
                )
                .0
        };
        let torso = link(
            &mut world,
            Vector::new(0.0, 0.0, 0.6),
            Vector::new(0.3, 0.05, 0.04),
        );
        let thigh = link(
            &mut world,
            Vector::new(0.5, 0.0, 0.6),
            Vector::new(0.1, 0.02, 0.04),
        );
        let arm = link(
            &mut world,
            Vector::new(0.0, 0.1, 0.6),
            Vector::new(0.12, 0.03, 0.03),
        );
        let hand = link(
            &mut world,
            Vector::new(0.24, 0.1, 0.6),
            Vector::new(0.06, 0.02, 0.03),
        );
        let planar = GenericJointBuilder::new(
            JointAxesMask::LIN_Y | JointAxesMask::ANG_X | JointAxesMask::ANG_Z,
        );
        let cylindrical = GenericJointBuilder::new(
            JointAxesMask::LIN_Y
                | JointAxesMask::LIN_Z
                | JointAxesMask::ANG_Y
                | JointAxesMask::ANG_Z,
        );
        let joints: [(RigidBodyHandle, RigidBodyHandle, GenericJoint, Vector); 4] = [
            (base, torso, planar.into(), Vector::ZERO),
            (
                torso,
                thigh,
                RevoluteJointBuilder::new(Vector::Y).into(),
                Vector::new(0.5, 0.0, 0.0),
            ),
            (
                torso,
                arm,
                SphericalJointBuilder::new().into(),
                Vector::new(0.0, 0.1, 0.0),
            ),
            (arm, hand, cylindrical.into(), Vector::new(0.24, 0.0, 0.0)),
        ];
        let mut handle = None;
        for (parent, child, mut joint, anchor) in joints {
            joint.set_local_anchor1(anchor);
            handle = world.insert_multibody_joint(parent, child, joint);
        }
        let handle = handle.unwrap();
        let mb = world.multibody_joints.get_mut(handle).unwrap().0;
        mb.forward_kinematics(&world.bodies, false);
        assert_eq!(mb.ndofs(), 3 + 1 + 3 + 2);
        mb.apply_displacements(&[0.1, -0.05, 0.3, 0.6, 0.2, -0.4, 0.5, 0.03, 0.8]);
        mb.forward_kinematics(&world.bodies, false);
        mb.update_rigid_bodies(&mut world.bodies, true);
        mb.velocities
            .copy_from_slice(&[1.2, -0.4, 2.0, -1.5, 0.7, 1.1, -0.9, 0.3, 2.4]);
        mb.update_velocities(&mut world.bodies);
        // Sizes the matrices (moving: the link-by-link construction).
        mb.update_mass_matrix(DT, &world.bodies);
        let bodies = &world.bodies;
        assert!(!mb.composite_applies(bodies, true));
        assert!(mb.composite_applies(bodies, false));
        let (mass, _) = matrices(mb, |mb| mb.composite_mass_matrices(DT, false, bodies));
        let (link_mass, _) = matrices(mb, |mb| {
            for i in 0..mb.links.len() {
                let span = mb.links[i].assembly_id + mb.links[i].joint.ndofs();
                mb.accumulate_link_mass_3d(i, span, DT, false, bodies);
            }
        });
        let mass_error = relative_error(&mass, &link_mass);
        assert!(
            mass_error < 1.0e-6,
            "M: {mass_error:e}\n{mass}\n{link_mass}"
        );
        // The joints' own DoFs couple (a planar hinge with its slides, a ball's three axes).
        assert!(link_mass[(0, 2)].abs() > 1.0e-3 * link_mass.amax());
        assert!(link_mass[(4, 5)].abs() > 1.0e-3 * link_mass.amax());

        // `update_mass_matrix` takes the composite path when the velocity terms are explicit
        // (gymfleet patch 26) and builds the same `M`, in both triangles.
        mb.set_explicit_velocity_terms(true);
        mb.update_mass_matrix(DT, bodies);
        let full = mb.augmented_mass.clone();
        for a in 0..full.nrows() {
            for c in a..full.ncols() {
                let (entry, reference) = (full[(a, c)], link_mass[(a, c)] + diagonal(mb, a, c));
                assert!(
                    (entry - reference).abs() <= 1.0e-6 * link_mass.amax(),
                    "M[{a},{c}]"
                );
                assert_eq!(full[(c, a)], entry);
            }
        }
    }

    /// A planar root (slides along X and Z, a hinge about Y: MJCF's slide/slide/hinge roots as
    /// one joint) with a two-link leg (revolute Y, then revolute about a skew axis) and an arm
    /// (revolute X), displaced and moving: HalfCheetah's, Hopper's and Walker2d's shape.
    fn planar_tree() -> (PhysicsWorld, MultibodyJointHandle) {
        let mut world = PhysicsWorld::new();
        let base =
            world.insert_body(RigidBodyBuilder::fixed().translation(Vector::new(0.0, 0.0, 0.6)));
        let link = |world: &mut PhysicsWorld, at: Vector, half: Vector| {
            world
                .insert(
                    RigidBodyBuilder::dynamic().translation(at),
                    ColliderBuilder::cuboid(half.x, half.y, half.z)
                        .translation(Vector::new(half.x, 0.02, -0.01))
                        .density(700.0 + 100.0 * at.x),
                )
                .0
        };
        let torso = link(
            &mut world,
            Vector::new(0.0, 0.0, 0.6),
            Vector::new(0.3, 0.05, 0.04),
        );
        let thigh = link(
            &mut world,
            Vector::new(0.5, 0.0, 0.6),
            Vector::new(0.1, 0.02, 0.04),
        );
        let shin = link(
            &mut world,
            Vector::new(0.7, 0.0, 0.6),
            Vector::new(0.08, 0.02, 0.03),
        );
        let arm = link(
            &mut world,
            Vector::new(0.0, 0.1, 0.6),
            Vector::new(0.12, 0.03, 0.03),
        );
        let planar = GenericJointBuilder::new(
            JointAxesMask::LIN_Y | JointAxesMask::ANG_X | JointAxesMask::ANG_Z,
        );
        let skew = Vector::new(0.0, 1.0, 1.0).normalize();
        let joints: [(RigidBodyHandle, RigidBodyHandle, GenericJoint, Vector); 4] = [
            (base, torso, planar.into(), Vector::ZERO),
            (
                torso,
                thigh,
                RevoluteJointBuilder::new(Vector::Y).into(),
                Vector::new(0.5, 0.0, 0.0),
            ),
            (
                thigh,
                shin,
                RevoluteJointBuilder::new(skew).into(),
                Vector::new(0.2, 0.0, 0.0),
            ),
            (
                torso,
                arm,
                RevoluteJointBuilder::new(Vector::X).into(),
                Vector::new(0.0, 0.1, 0.0),
            ),
        ];
        let mut handle = None;
        for (parent, child, mut joint, anchor) in joints {
            joint.set_local_anchor1(anchor);
            handle = world.insert_multibody_joint(parent, child, joint);
        }
        let handle = handle.unwrap();
        let mb = world.multibody_joints.get_mut(handle).unwrap().0;
        mb.forward_kinematics(&world.bodies, false);
        assert_eq!(mb.ndofs(), 3 + 1 + 1 + 1);
        mb.apply_displacements(&[0.1, -0.05, 0.3, 0.6, -0.4, 0.5]);
        mb.forward_kinematics(&world.bodies, false);
        mb.update_rigid_bodies(&mut world.bodies, true);
        mb.velocities
            .copy_from_slice(&[1.2, -0.4, 2.0, -1.5, 0.7, 2.4]);
        mb.update_velocities(&mut world.bodies);
        mb.update_mass_matrix(DT, &world.bodies);
        (world, handle)
    }

    /// With the velocity terms, a planar joint takes the composite construction (patch 31):
    /// `M` as link by link, `dt·D` the derivative of the forces `update_acceleration` applies
    /// (measured: 1e-7 off it), and `update_mass_matrix` builds them.
    #[test]
    fn a_planar_root_builds_both_matrices_by_composite_bodies() {
        let (mut world, handle) = planar_tree();
        let derivative = velocity_derivative(&mut world, handle);
        let bodies = &world.bodies;
        let mb = world.multibody_joints.get_mut(handle).unwrap().0;
        assert!(mb.composite_applies(bodies, true));
        let update_velocity = &mb.acc_augmented_mass - &mb.augmented_mass;
        let update_error = relative_error(&update_velocity, &derivative);
        assert!(
            update_error < 1.0e-4,
            "update_mass_matrix's dt·D: {update_error:e}"
        );
        let (mass, velocity) = matrices(mb, |mb| mb.composite_mass_matrices(DT, true, bodies));
        let (link_mass, _) = matrices(mb, |mb| {
            for i in 0..mb.links.len() {
                let span = mb.links[i].assembly_id + mb.links[i].joint.ndofs();
                mb.accumulate_link_mass_3d(i, span, DT, true, bodies);
            }
        });
        let mass_error = relative_error(&mass, &link_mass);
        assert!(
            mass_error < 1.0e-6,
            "M: {mass_error:e}\n{mass}\n{link_mass}"
        );
        let velocity_error = relative_error(&velocity, &derivative);
        assert!(
            velocity_error < 1.0e-5,
            "dt·D: {velocity_error:e}\n{velocity}\n{derivative}"
        );
        // The slides and the hinge couple, and the terms are neither zero nor symmetric.
        assert!(link_mass[(0, 2)].abs() > 1.0e-3 * link_mass.amax());
        assert!(derivative.amax() > 1.0e-4 * link_mass.amax());
        assert!((&derivative - derivative.transpose()).amax() > 0.1 * derivative.amax());
    }

    /// The planar tree moving without gravity, contacts or damping for 2 s (480 steps) on the
    /// composite construction with its velocity terms: its energy stays within 0.5 % of its
    /// start (measured: −0.01 % to +0.16 %; the link-by-link construction, upstream's terms,
    /// moves it the same way: −0.01 % to +0.16 %).
    #[test]
    fn a_planar_tree_moving_freely_gains_no_energy() {
        let (mut world, handle) = planar_tree();
        world.gravity = Vector::ZERO;
        world.integration_parameters.dt = 1.0 / 240.0;
        world.integration_parameters.num_solver_iterations = 4;
        for (_, collider) in world.colliders.iter_mut() {
            collider.set_collision_groups(InteractionGroups::none());
        }
        world
            .multibody_joints
            .get_mut(handle)
            .unwrap()
            .0
            .damping_mut()
            .fill(0.0);
        world.step();
        let mb = world.multibody_joints.get(handle).unwrap().0;
        assert!(mb.composite_applies(&world.bodies, true));
        // The moving links' kinetic energy (the fixed base has none, and no finite inertia).
        let kinetic = |world: &PhysicsWorld| -> Real {
            let moving = world.bodies.iter().filter(|(_, rb)| rb.is_dynamic());
            moving
                .map(|(_, rb)| {
                    let (m, v, w) = (rb.mass(), rb.linvel(), rb.angvel());
                    let inertia = rb.mprops.effective_world_inv_inertia.inverse_unchecked();
                    0.5 * (m * v.length_squared() + w.dot(inertia * w))
                })
                .sum()
        };
        let energy0 = kinetic(&world);
        for _ in 0..480 {
            world.step();
            let energy = kinetic(&world);
            assert!(
                (energy / energy0 - 1.0).abs() < 0.005,
                "{energy} from {energy0}"
            );
        }
    }

    /// What `update_mass_matrix` adds to `M[a, c]` besides the links: damping and armature.
    fn diagonal(mb: &Multibody, a: usize, c: usize) -> Real {
        if a == c {
            mb.damping[a] * DT + mb.armature[a]
        } else {
            0.0
        }
    }
}
