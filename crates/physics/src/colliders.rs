//! Bodies and their colliders from instances: each instance's pose, its exact primitive
//! collider (a mesh's hull or decomposition), its mass (volume × density, or its given
//! inertial) and collision groups, and the robot's reach (for soft CCD).

use gymfleet_assembly::{Instance, Shape, SoftContact, MM_PER_M};
use rapier3d::geometry::ContactCompliance;
use rapier3d::prelude::*;

use crate::world::Sets;

pub(crate) fn instance_pose(inst: &Instance) -> Pose {
    let [x, y, z] = inst.position.map(|c| c as Real);
    let [rx, ry, rz] = inst.rotation.map(|c| c as Real);
    // X, then Y, then Z about fixed axes: R = Rz · Ry · Rx.
    let rotation = Rotation::from_rotation_z(rz)
        * Rotation::from_rotation_y(ry)
        * Rotation::from_rotation_x(rx);
    Pose::from_parts(Vector::new(x, y, z), rotation)
}

/// Inserts an instance's body (fixed, dynamic, or kinematic for a mocap body) at its
/// document pose, with its collider;
/// returns both. Its given mass properties are set by [`set_given_masses`].
pub(crate) fn insert_body(
    sets: &mut Sets,
    inst: &Instance,
    fixed: bool,
) -> (RigidBodyHandle, ColliderHandle) {
    let builder = if inst.mocap {
        // Moved by its pose targets (`free_bodies.rs`).
        RigidBodyBuilder::kinematic_position_based()
    } else if fixed {
        RigidBodyBuilder::fixed()
    } else {
        RigidBodyBuilder::dynamic().can_sleep(false)
    };
    let handle = sets
        .bodies
        .insert(builder.pose(instance_pose(inst)).build());
    let collider = attach_collider(sets, inst, handle, Pose::IDENTITY);
    (handle, collider)
}

/// Attaches an instance's collider to `body`, the instance's frame at `frame` in the
/// body's frame (the identity on a body of its own).
pub(crate) fn attach_collider(
    sets: &mut Sets,
    inst: &Instance,
    body: RigidBodyHandle,
    frame: Pose,
) -> ColliderHandle {
    let (group, mask) = inst.collision;
    // Given mass properties replace the collider's: its density is then 0.
    let density = if inst.inertial.is_some() {
        0.0
    } else {
        inst.material.density as Real
    };
    let collider = match exact_mass_properties(&inst.shape, density) {
        Some(props) => collider(&inst.shape).mass_properties(props),
        None => collider(&inst.shape).density(density),
    };
    let mut collider = collider
        .friction(inst.material.friction as Real)
        .restitution(inst.material.restitution as Real)
        // MuJoCo's rule: `a.group & b.mask` or `b.group & a.mask` (see `Instance::collision`).
        .collision_groups(InteractionGroups::new(
            Group::from_bits_retain(group),
            Group::from_bits_retain(mask),
            InteractionTestMode::Or,
        ));
    collider.position = frame * collider.position;
    let mut collider = collider.build();
    if let Some(soft) = inst.material.soft_contact {
        // MuJoCo's friction of two geoms is the larger.
        collider.set_friction_combine_rule(CoefficientCombineRule::Max);
        collider.set_compliance(Some(compliance(soft)));
    }
    sets.colliders
        .insert_with_parent(collider, body, &mut sets.bodies)
}

/// Sets each compliant collider's inverse weight (MuJoCo's `body_invweight0`, the
/// regulariser's scale; vendored patch 43) from its body at the current pose: a multibody
/// link's from the joint-space inertia, a body that cannot turn (sliders only) `1/m` as
/// MuJoCo's simple bodies, a free body's `1/m`, a fixed body's 0; and each compliant limit's
/// (patch 44), the DOF's inverse inertia (MuJoCo's `dof_invweight0`). Given masses reach
/// the bodies at the first step, so they are weighed on a copy that has them now.
pub(crate) fn set_invweights(sets: &mut Sets) {
    let mut weighed = sets.clone();
    let handles: Vec<RigidBodyHandle> = weighed.bodies.iter().map(|(h, _)| h).collect();
    for h in handles {
        let colliders = &weighed.colliders;
        weighed.bodies[h].recompute_mass_properties_from_colliders(colliders);
    }
    let compliant: Vec<(ColliderHandle, RigidBodyHandle)> = sets
        .colliders
        .iter()
        .filter(|(_, c)| c.compliance().is_some())
        .filter_map(|(h, c)| Some((h, c.parent()?)))
        .collect();
    let mut weights: std::collections::HashMap<RigidBodyHandle, Real> = Default::default();
    for (collider, body) in compliant {
        let weight = *weights
            .entry(body)
            .or_insert_with(|| body_invweight(&mut weighed, body));
        let c = &mut sets.colliders[collider];
        let compliance = c.compliance().copied().map(|mut k| {
            k.invweight = weight;
            k
        });
        c.set_compliance(compliance);
    }
    set_limit_invweights(sets, &mut weighed);
}

/// Each compliant limit's inverse weight: its DOF's `(M⁻¹)ᵢᵢ` on the weighed copy.
fn set_limit_invweights(sets: &mut Sets, weighed: &mut Sets) {
    let mut multibodies: Vec<MultibodyIndex> = sets
        .multibody_joints
        .iter()
        .map(|(_, link, _, _)| link.multibody)
        .collect();
    multibodies.dedup();
    for index in multibodies {
        let Some(mb) = sets.multibody_joints.get_multibody_mut(index) else {
            continue;
        };
        if !(0..mb.num_links()).any(|l| {
            mb.link(l)
                .is_some_and(|k| k.joint.limit_compliance().is_some())
        }) {
            continue;
        }
        let Some(copy) = weighed.multibody_joints.get_multibody_mut(index) else {
            continue;
        };
        let inverse = copy.dof_inverse_inertia(&weighed.bodies);
        for l in 0..mb.num_links() {
            let Some(link) = mb.link_mut(l) else { continue };
            let dof = link.assembly_id();
            if let Some(mut c) = link.joint.limit_compliance().copied() {
                c.invweight = inverse[dof];
                link.joint.set_limit_compliance(Some(c));
            }
        }
    }
}

fn body_invweight(sets: &mut Sets, body: RigidBodyHandle) -> Real {
    let rb = &sets.bodies[body];
    if !rb.is_dynamic() {
        return 0.0;
    }
    let inv_mass = rb.mass_properties().local_mprops.inv_mass;
    let Some(link) = sets.multibody_joints.rigid_body_link(body).copied() else {
        return inv_mass;
    };
    let Some(mb) = sets.multibody_joints.get_multibody_mut(link.multibody) else {
        return inv_mass;
    };
    let (tran, rot) = mb.body_invweight(&sets.bodies, link.id);
    if rot <= 1e-12 * tran.max(1.0) {
        inv_mass
    } else {
        tran
    }
}

/// A material's compliant contact as Rapier's (vendored patch 43), lengths in metres.
fn compliance(soft: SoftContact) -> ContactCompliance {
    let m = |mm: f64| (mm / MM_PER_M) as Real;
    let [dmin, dmax, width, midpoint, power] = soft.solimp;
    ContactCompliance {
        solref: soft.solref.map(|v| v as Real),
        solimp: [dmin, dmax, width / MM_PER_M, midpoint, power].map(|v| v as Real),
        solmix: soft.solmix as Real,
        priority: soft.priority,
        margin: m(soft.margin),
        gap: m(soft.gap),
        pyramidal: soft.pyramidal,
        impratio: soft.impratio as Real,
        // Set from the body once the trees are built (`set_invweights`).
        invweight: 0.0,
        condim: soft.condim as u8,
        torsional: m(soft.torsional_friction),
        rolling: m(soft.rolling_friction),
        // MuJoCo's pyramid as its four facets (vendored patch 51).
        facets: true,
    }
}

/// Sets each body's additional mass properties: the sum of the given ones (`given`, each
/// in its instance's frame) of the instances on it, placed by `placements`. Bodies whose
/// instances give none keep their colliders'. With `recompute`, each body's mass is
/// recomputed from them now; else Rapier applies them at the next step, as it always
/// has at build (the default gains are resolved before that step).
pub(crate) fn set_given_masses(
    sets: &mut Sets,
    bodies: &[RigidBodyHandle],
    owners: &[usize],
    placements: &[Pose],
    given: &[Option<MassProperties>],
    recompute: bool,
) {
    // Each owner's sum, in one pass over the instances.
    let mut sums: Vec<Option<MassProperties>> = vec![None; bodies.len()];
    for (i, props) in given.iter().enumerate() {
        if let Some(props) = props {
            let placed = props.transform_by(&placements[i]);
            let sum = &mut sums[owners[i]];
            *sum = Some(sum.map_or(placed, |s| s + placed));
        }
    }
    for owner in (0..bodies.len()).filter(|&i| owners[i] == i) {
        if let Some(rb) = sets.bodies.get_mut(bodies[owner]) {
            if let Some(sum) = sums[owner] {
                rb.set_additional_mass_properties(sum, false);
            }
            if recompute {
                rb.recompute_mass_properties_from_colliders(&sets.colliders);
            }
        }
    }
}

/// An instance's given mass properties in its body's frame: its inertia matrix, or the
/// shape's own inertia scaled to the given mass, about the given centre of mass.
pub(crate) fn given_mass_properties(
    inertial: &gymfleet_assembly::Inertial,
    shape: &Shape,
) -> MassProperties {
    let c = inertial.center_of_mass.map(|v| v as Real);
    let com = Vector::new(c[0], c[1], c[2]);
    let mass = inertial.mass as Real;
    match inertial.inertia {
        Some(m) => {
            let m = m.map(|row| row.map(|v| v as Real));
            let matrix = Mat3::from_cols(
                Vector::new(m[0][0], m[1][0], m[2][0]),
                Vector::new(m[0][1], m[1][1], m[2][1]),
                Vector::new(m[0][2], m[1][2], m[2][2]),
            );
            MassProperties::with_inertia_matrix(com, mass, matrix)
        }
        None if exact_mass_properties(shape, 1.0).is_some() => {
            let own = exact_mass_properties(shape, 1.0).expect("checked");
            MassProperties::new(com, mass, own.principal_inertia() * (mass / own.mass()))
        }
        None => {
            // The shape's own, at unit density, placed as the collider is, then scaled. The
            // collider has no parent: its pose in the part (a capsule turned from Rapier's Y
            // onto the part's Z, a shape moved off its centre) is its `position`.
            let unit = collider(shape).density(1.0).build();
            let own = unit
                .shape()
                .mass_properties(1.0)
                .transform_by(unit.position());
            let mut props = MassProperties::with_principal_inertia_frame(
                com,
                own.mass(),
                own.principal_inertia(),
                own.principal_inertia_local_frame,
            );
            props.set_mass(mass, true);
            props
        }
    }
}

/// A shape's mass properties at `density` where its collider is only an approximation of
/// it, which Rapier would weigh by the approximation: an ellipsoid's (centred, principal
/// along its axes, `m/5 · (b² + c², a² + c², a² + b²)`). `None` for the others, and for a
/// density of 0 (a given mass).
pub(crate) fn exact_mass_properties(shape: &Shape, density: Real) -> Option<MassProperties> {
    let Shape::Ellipsoid {
        radii: [a, b, c], ..
    } = *shape
    else {
        return None;
    };
    if density <= 0.0 {
        return None;
    }
    let mass = f64::from(density) * 4.0 / 3.0 * std::f64::consts::PI * a * b * c;
    let i = |p: f64, q: f64| (mass / 5.0 * (p * p + q * q)) as Real;
    Some(MassProperties::new(
        Vector::ZERO,
        mass as Real,
        Vector::new(i(b, c), i(a, c), i(a, b)),
    ))
}

/// The exact primitive, placed in the part's frame (cube corner, cylinder and capsule base
/// at the origin; Rapier's cylinder and capsule run along Y, ours along Z).
pub(crate) fn collider(shape: &Shape) -> ColliderBuilder {
    match *shape {
        Shape::Cuboid { size } => {
            let half = size.map(|c| (c / 2.0) as Real);
            ColliderBuilder::cuboid(half[0], half[1], half[2])
                .translation(Vector::new(half[0], half[1], half[2]))
        }
        Shape::Cylinder { radius, height } => {
            let half_height = (height / 2.0) as Real;
            ColliderBuilder::cylinder(half_height, radius as Real).position(Pose::from_parts(
                Vector::new(0.0, 0.0, half_height),
                Rotation::from_rotation_x(std::f32::consts::FRAC_PI_2),
            ))
        }
        Shape::Sphere { radius } => ColliderBuilder::ball(radius as Real),
        Shape::Capsule { radius, height } => {
            let half_segment = ((height / 2.0 - radius).max(0.0)) as Real;
            ColliderBuilder::capsule_y(half_segment, radius as Real).position(Pose::from_parts(
                Vector::new(0.0, 0.0, (height / 2.0) as Real),
                Rotation::from_rotation_x(std::f32::consts::FRAC_PI_2),
            ))
        }
        Shape::Plane => ColliderBuilder::halfspace(rapier3d::na::Unit::new_unchecked(Vector::Z)),
        Shape::Heightfield(ref field) => {
            ColliderBuilder::new(heightfield_shape(field)).position(heightfield_pose())
        }
        // An ellipsoid is its polyhedron, whose volume is the ellipsoid's: its mass is the
        // ellipsoid's, its inertia within about 1 % of it.
        Shape::Convex(ref parts)
        | Shape::Ellipsoid {
            hull: ref parts, ..
        } => {
            let mut shapes: Vec<(Pose, SharedShape)> = parts
                .pieces
                .iter()
                .map(|piece| {
                    let vertices = piece
                        .vertices
                        .iter()
                        .map(|v| Vector::new(v[0] as Real, v[1] as Real, v[2] as Real))
                        .collect();
                    let shape = SharedShape::convex_mesh(vertices, &piece.triangles)
                        .expect("gymfleet_assembly built this polyhedron from these very points");
                    (Pose::IDENTITY, shape)
                })
                .collect();
            if shapes.len() == 1 {
                ColliderBuilder::new(shapes.remove(0).1)
            } else {
                ColliderBuilder::compound(shapes)
            }
        }
    }
}

/// A heightfield as Parry's (its grid on its x–z plane, heights along y; internal edges
/// fixed, so that what rolls across cells feels no bump): Parry's row `i` runs along its z,
/// which [`heightfield_pose`] turns to −y, so it is the document's row `rows − 1 − i`.
pub(crate) fn heightfield_shape(field: &gymfleet_assembly::Heightfield) -> SharedShape {
    let (rows, columns) = (field.rows, field.columns);
    let mut data = Vec::with_capacity(rows * columns);
    // Column-major: Parry's (i, j) at i + j·rows.
    for j in 0..columns {
        for i in 0..rows {
            data.push(field.heights[(rows - 1 - i) * columns + j] as Real);
        }
    }
    let scale = Vector::new(
        (2.0 * field.half_extents[0]) as Real,
        field.elevation as Real,
        (2.0 * field.half_extents[1]) as Real,
    );
    SharedShape::heightfield_with_flags(
        rapier3d::parry::utils::Array2::new(rows, columns, data),
        scale,
        HeightFieldFlags::FIX_INTERNAL_EDGES,
    )
}

/// Where a heightfield's Parry shape sits in its part's frame: Parry's y (up) along z.
pub(crate) fn heightfield_pose() -> Pose {
    Pose::from_parts(
        Vector::ZERO,
        Rotation::from_rotation_x(std::f32::consts::FRAC_PI_2),
    )
}

/// The diagonal of the box that holds every collider at the initial pose, in m.
pub(crate) fn assembly_reach(colliders: &ColliderSet) -> Real {
    let mut all: Option<Aabb> = None;
    // A ground (a plane, unbounded; terrain) is not the robot: its size is its other
    // parts'.
    for (_, co) in colliders.iter().filter(|(_, co)| {
        co.shape().as_halfspace().is_none() && co.shape().as_heightfield().is_none()
    }) {
        let aabb = co.compute_aabb();
        all = Some(all.map_or(aabb, |a| a.merged(&aabb)));
    }
    all.map_or(1.0, |a| (a.maxs - a.mins).length())
}
