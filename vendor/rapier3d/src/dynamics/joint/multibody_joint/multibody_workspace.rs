use crate::alloc_prelude::*;
use crate::dynamics::RigidBodyVelocity;
use crate::math::Vector;
use crate::math::{AngularInertia, DVector, Real};

/// One column (DoF) of a link's contribution to the mass matrices: the products of its
/// body-jacobian column the mass matrices are built from (gymfleet patch).
#[cfg(feature = "dim3")]
#[derive(Copy, Clone, Debug, Default)]
pub(crate) struct MassColumn {
    pub mass_jv: Vector,
    pub inertia_jw: Vector,
    pub acc_v: Vector,
    pub acc_w: Vector,
}

/// A temporary workspace for various updates of the multibody.
#[cfg_attr(feature = "serde-serialize", derive(Serialize, Deserialize))]
#[derive(Clone, Debug)]
pub(crate) struct MultibodyWorkspace {
    pub accs: Vec<RigidBodyVelocity<Real>>,
    /// Per link, its effective mass and world-space angular inertia at this substep's
    /// configuration (`Multibody::update_link_inertias`), computed once for both the mass
    /// matrices and the accelerations (gymfleet patch 35).
    #[cfg_attr(feature = "serde-serialize", serde(skip))]
    pub link_inertias: Vec<(Vector, AngularInertia)>,
    pub ndofs_vec: DVector,
    /// Buffers of `update_acceleration` and its energy guard, reused from one substep to
    /// the next (gymfleet patch).
    pub pos_forces: DVector,
    pub gen_forces: DVector,
    pub guard_v: DVector,
    pub guard_f: DVector,
    pub guard_f_pos: DVector,
    pub guard_a: DVector,
    pub guard_m_x: DVector,
    #[cfg(feature = "dim3")]
    #[cfg_attr(feature = "serde-serialize", serde(skip))]
    pub mass_columns: Vec<MassColumn>,
    /// Per link, the force and torque at its centre of mass that `update_acceleration`
    /// projects, summed over its subtree by the backward pass (gymfleet patch 33).
    #[cfg(feature = "dim3")]
    #[cfg_attr(feature = "serde-serialize", serde(skip))]
    pub wrenches: Vec<[Vector; 2]>,
    /// The same for the applied forces alone, for the energy guard (gymfleet patch 33).
    #[cfg(feature = "dim3")]
    #[cfg_attr(feature = "serde-serialize", serde(skip))]
    pub applied_wrenches: Vec<[Vector; 2]>,
    /// The six rows of a body jacobian, each contiguous (gymfleet patch).
    #[cfg(feature = "dim3")]
    #[cfg_attr(feature = "serde-serialize", serde(skip))]
    pub jacobian_rows: [Vec<Real>; 6],
}

impl MultibodyWorkspace {
    /// Create an empty workspace.
    pub fn new() -> Self {
        MultibodyWorkspace {
            accs: Vec::new(),
            link_inertias: Vec::new(),
            ndofs_vec: DVector::zeros(0),
            pos_forces: DVector::zeros(0),
            gen_forces: DVector::zeros(0),
            guard_v: DVector::zeros(0),
            guard_f: DVector::zeros(0),
            guard_f_pos: DVector::zeros(0),
            guard_a: DVector::zeros(0),
            guard_m_x: DVector::zeros(0),
            #[cfg(feature = "dim3")]
            mass_columns: Vec::new(),
            #[cfg(feature = "dim3")]
            wrenches: Vec::new(),
            #[cfg(feature = "dim3")]
            applied_wrenches: Vec::new(),
            #[cfg(feature = "dim3")]
            jacobian_rows: Default::default(),
        }
    }

    /// Resize the workspace so it is enough for `nlinks` links.
    pub fn resize(&mut self, nlinks: usize, ndofs: usize) {
        self.accs.resize(nlinks, RigidBodyVelocity::zero());
        self.ndofs_vec = DVector::zeros(ndofs)
    }
}
