//! Planar roots as one Rapier joint. A robot that moves in a plane (HalfCheetah: `rootx`,
//! `rootz`, `rooty`) comes from its document as a slide, a second slide and a hinge chained
//! through two helper instances (the MJCF conversion's 1 mg spheres that collide with
//! nothing). As links of a tree, the helpers cost a link's kinematics, mass-matrix and
//! solver work each per substep. Here the chain becomes one joint of the same three DOFs:
//! linear X and Z and angular Y of a frame whose X is the first slide's axis and whose Y is
//! the hinge's (the second slide must then be Z = X × Y). Rapier orders its DOFs X, Z, Y:
//! the chain's order. The helpers are folded into the body below, so their 1 mg rides on
//! it. Where their centres lie on the hinge's axis (the conversion puts them at the body's
//! frame, where HalfCheetah's, Hopper's and Walker2d's hinges are), only their share of the
//! slides' motion changes (under 1e-7 of HalfCheetah's mass). Their readouts stay exact
//! ([`PlanarHelper`]).
//!
//! The joint's matrices are built by composite bodies, as the chain's are: its mass matrix
//! (vendored Rapier patch 30) and, where the velocity terms enter the semi-implicit matrix
//! (files not integrated with `Euler`), their derivative (patch 31). A chain whose helpers
//! carry a site, in a world with a fluid (whose drag is per body), or whose top is not held
//! fixed stays a chain.

use gymfleet_assembly::{Assembly, JointType};
use rapier3d::math::Matrix;
use rapier3d::prelude::*;

use crate::world::{Lane, PlanarHelper};

/// The most mass (kg) an instance between the chain's joints may have to be left out of
/// its slides' motion: the conversion's helpers have 1 mg.
const HELPER_MASS_CAP: f64 = 1e-5;
/// How far from orthogonal (and from X × Y) the chain's axes may be.
const AXIS_TOLERANCE: f64 = 1e-9;
/// The fused joint's free axes, in the chain's order (first slide, second slide, hinge),
/// which is Rapier's DOF order too.
const FUSED_AXES: [JointAxis; 3] = [JointAxis::LinX, JointAxis::LinZ, JointAxis::AngY];

/// One chain fused into a joint.
#[derive(Debug, Clone)]
pub(crate) struct PlanarRoot {
    /// First slide, second slide, hinge.
    pub(crate) joints: [usize; 3],
    /// The helper instances between them.
    pub(crate) helpers: [usize; 2],
    /// The fixed instance above the chain.
    pub(crate) parent: usize,
    /// The instance the hinge moves.
    pub(crate) body: usize,
    /// The joint frame in the world at the document's pose: origin at the hinge's anchor,
    /// X along the first slide, Y along the hinge.
    pub(crate) frame: Pose,
}

/// The chains to fuse, each once.
pub(crate) fn planar_roots(assembly: &Assembly, held: &[bool]) -> Vec<PlanarRoot> {
    if assembly.fluid.is_some() {
        return Vec::new();
    }
    let n = assembly.instances.len();
    let mut as_parent = vec![0usize; n];
    let mut as_child: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (j, joint) in assembly.joints.iter().enumerate() {
        as_parent[joint.parent] += 1;
        as_child[joint.child].push(j);
    }
    // The joint a helper hangs on: the only one it is the child of, and it heads exactly
    // one joint (the next of the chain).
    let chain_joint = |helper: usize, kind: JointType| -> Option<usize> {
        let instance = &assembly.instances[helper];
        let light = instance.inertial.is_some_and(|i| i.mass <= HELPER_MASS_CAP);
        let free = !held[helper]
            && instance.collision == (0, 0)
            && light
            && as_parent[helper] == 1
            && as_child[helper].len() == 1
            && !assembly.sites.iter().any(|s| s.instance == helper);
        let &[j] = as_child[helper].as_slice() else {
            return None;
        };
        let joint = &assembly.joints[j];
        (free && joint.kind == kind && !joint.closes_loop && !joint.on_loop).then_some(j)
    };
    let mut roots = Vec::new();
    for (hinge, joint) in assembly.joints.iter().enumerate() {
        if joint.kind != JointType::Revolute || joint.closes_loop || joint.on_loop {
            continue;
        }
        let second_helper = joint.parent;
        let Some(second) = chain_joint(second_helper, JointType::Prismatic) else {
            continue;
        };
        let first_helper = assembly.joints[second].parent;
        let Some(first) = chain_joint(first_helper, JointType::Prismatic) else {
            continue;
        };
        let parent = assembly.joints[first].parent;
        if !held[parent] || held[joint.child] {
            continue;
        }
        let axis = |j: usize| unit(assembly.joints[j].axis);
        let (x, y, z) = (axis(first), axis(hinge), axis(second));
        let xy = cross(x, y);
        let off = (0..3).map(|k| (xy[k] - z[k]).abs()).fold(0.0, f64::max);
        if dot(x, y).abs() > AXIS_TOLERANCE || off > AXIS_TOLERANCE {
            continue;
        }
        let column = |v: [f64; 3]| Vector::new(v[0] as Real, v[1] as Real, v[2] as Real);
        let rotation = Rotation::from_mat3(&Matrix::from_cols(column(x), column(y), column(z)));
        let [px, py, pz] = joint.anchor.map(|c| c as Real);
        let frame = Pose::from_parts(Vector::new(px, py, pz), rotation.normalize());
        roots.push(PlanarRoot {
            joints: [first, second, hinge],
            helpers: [first_helper, second_helper],
            parent,
            body: joint.child,
            frame,
        });
    }
    roots
}

fn unit(v: [f64; 3]) -> [f64; 3] {
    let n = dot(v, v).sqrt();
    v.map(|c| c / n)
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Each joint's lane in a fused joint, `None` for a joint that keeps its own link.
pub(crate) fn lanes(assembly: &Assembly, roots: &[PlanarRoot]) -> Vec<Option<Lane>> {
    let mut lanes = vec![None; assembly.joints.len()];
    for root in roots {
        for (offset, (&j, axis)) in root.joints.iter().zip(FUSED_AXES).enumerate() {
            lanes[j] = Some(Lane { offset, axis });
        }
    }
    lanes
}

/// Folds each chain's helpers into the body the chain moves.
pub(crate) fn fold_helpers(roots: &[PlanarRoot], owners: &mut [usize]) {
    for root in roots {
        for &h in &root.helpers {
            owners[h] = root.body;
        }
    }
}

/// The fused joint between the parent's body and the moving one (frames in each body's
/// local frame at the document's pose), with the chain's limits on their axes.
pub(crate) fn fused_joint(
    assembly: &Assembly,
    root: &PlanarRoot,
    parent_pose: &Pose,
    body_pose: &Pose,
    contacts: bool,
) -> GenericJoint {
    let locked = JointAxesMask::LIN_Y | JointAxesMask::ANG_X | JointAxesMask::ANG_Z;
    let mut builder = GenericJointBuilder::new(locked)
        .local_frame1(parent_pose.inverse() * root.frame)
        .local_frame2(body_pose.inverse() * root.frame)
        .contacts_enabled(contacts);
    for (&j, axis) in root.joints.iter().zip(FUSED_AXES) {
        if let Some([min, max]) = assembly.joints[j].limits {
            builder = builder.limits(axis, [min as Real, max as Real]);
        }
    }
    builder.build()
}

/// The helpers' readouts: each helper moves with the slides above it and keeps the fixed
/// parent's orientation. Slots are in document order, so a joint's slot is its index.
pub(crate) fn helpers(roots: &[PlanarRoot], instance_poses: &[Pose]) -> Vec<PlanarHelper> {
    let mut out = Vec::new();
    for root in roots {
        for (k, &h) in root.helpers.iter().enumerate() {
            out.push(PlanarHelper {
                instance: h,
                slot: root.joints[0],
                slides: k + 1,
                frame: root.frame,
                rest: root.frame.inverse() * instance_poses[h],
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use gymfleet_assembly::Assembly;

    use crate::{ActionMode, RobotWorld, Units, WorldOptions};

    /// A bar on a slide (X), a second slide (Z, sprung and damped) and a hinge (Y, with
    /// armature and ±40° stops), chained through two 1 mg helpers from a grounded base:
    /// it drops, bobs on the spring and swings into a stop. With `site`, a site on the
    /// second helper keeps the chain; `integrator` is the document's.
    fn planar(site: bool, integrator: &str) -> Assembly {
        let sites = if site {
            r#", "sites": [{ "name": "mark", "instance": "h2", "point": { "x": 0, "y": 0, "z": 0 } }]"#
        } else {
            ""
        };
        let helper = |name: &str| {
            format!(
                r#"{{ "part": "Dot", "name": "{name}", "position": {{ "x": 50, "y": 50, "z": 200 }},
                     "collision": {{ "group": 0, "mask": 0 }}, "inertial": {{ "mass": 1e-6 }} }}"#
            )
        };
        let doc = format!(
            r#"{{
  "parts": [
    {{ "name": "Base", "primitive": {{ "type": "cube", "size": {{ "x": 100, "y": 100, "z": 10 }} }} }},
    {{ "name": "Dot", "primitive": {{ "type": "sphere", "radius": 1 }} }},
    {{ "name": "Bar", "primitive": {{ "type": "cube", "size": {{ "x": 80, "y": 20, "z": 20 }} }} }}
  ],
  "simulation": {{ "integrator": "{integrator}" }},
  "assembly": {{
    "instances": [
      {{ "part": "Base", "name": "base" }},
      {h1}, {h2},
      {{ "part": "Bar", "name": "bar", "position": {{ "x": 50, "y": 40, "z": 190 }} }}
    ],
    "joints": [
      {{ "type": "prismatic", "name": "x", "parent": "base", "child": "h1", "initial": 10,
         "anchor": {{ "x": 50, "y": 50, "z": 200 }}, "axis": {{ "x": 1, "y": 0, "z": 0 }} }},
      {{ "type": "prismatic", "name": "z", "parent": "h1", "child": "h2", "stiffness": 20,
         "damping": 0.05, "anchor": {{ "x": 50, "y": 50, "z": 200 }},
         "axis": {{ "x": 0, "y": 0, "z": 1 }} }},
      {{ "type": "revolute", "name": "pitch", "parent": "h2", "child": "bar", "min": -40,
         "max": 40, "armature": 1e-5, "anchor": {{ "x": 50, "y": 50, "z": 200 }},
         "axis": {{ "x": 0, "y": 1, "z": 0 }} }}
    ]{sites}
  }}
}}"#,
            h1 = helper("h1"),
            h2 = helper("h2"),
        );
        gymfleet_assembly::parse(&doc).unwrap()
    }

    fn links(world: &RobotWorld) -> usize {
        let trees = world.live.multibody_joints.multibodies();
        trees.map(|mb| mb.num_links()).sum()
    }

    fn joint_state(world: &RobotWorld) -> [f32; 6] {
        let (mut q, mut v) = ([0.0; 3], [0.0; 3]);
        world.joint_state(Units::Si, &mut q, &mut v);
        [q[0], q[1], q[2], v[0], v[1], v[2]]
    }

    fn built(site: bool, integrator: &str) -> RobotWorld {
        let mut world =
            RobotWorld::new(&planar(site, integrator), &WorldOptions::default()).expect("builds");
        world.set_command(ActionMode::Torque, &[0.0; 3]);
        world
    }

    /// The fused bar and the chain after `steps` steps.
    fn both_after(steps: usize) -> (RobotWorld, RobotWorld) {
        let (mut fused, mut chain) = (built(false, "euler"), built(true, "euler"));
        for _ in 0..steps {
            fused.step().unwrap();
            chain.step().unwrap();
        }
        (fused, chain)
    }

    #[test]
    fn a_chain_of_two_slides_and_a_hinge_through_helpers_is_one_joint() {
        let fused = built(false, "euler");
        // The base (the tree's fixed root) and the bar; the chain has two links more.
        assert_eq!(links(&fused), 2);
        assert_eq!(
            links(&built(true, "euler")),
            4,
            "a site on a helper keeps the chain"
        );
        assert_eq!(
            links(&built(false, "implicit")),
            2,
            "implicit velocity terms too (vendored Rapier patch 31)"
        );
        let lanes: Vec<_> = fused
            .joints
            .iter()
            .map(|s| s.lane.map(|l| l.offset))
            .collect();
        assert_eq!(lanes, [Some(0), Some(1), Some(2)]);
        // The DOFs' action bounds and default gains are the chain's (to its helpers' mass).
        let chain = built(true, "euler");
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-3 * b.abs();
        for (a, b) in fused.dofs.iter().zip(&chain.dofs) {
            assert!(close(a.action_bound, b.action_bound), "{a:?} {b:?}");
            assert!(close(a.kp, b.kp) && close(a.kd, b.kd), "{a:?} {b:?}");
        }
        // Where the document starts it: x at its initial 10 mm, the rest at rest.
        let start = joint_state(&fused);
        assert!((start[0] - 0.010).abs() < 1e-7, "{start:?}");
        assert_eq!(start[1..], [0.0; 5]);
    }

    /// Steps both 480 times; widens `worst` to each state's largest difference; whether the
    /// fused bar's pitch passed 0.69 rad (the +40° stop).
    fn step_both(fused: &mut RobotWorld, chain: &mut RobotWorld, worst: &mut [f32; 6]) -> bool {
        let mut stopped = false;
        for _ in 0..480 {
            fused.step().unwrap();
            chain.step().unwrap();
            let (a, b) = (joint_state(fused), joint_state(chain));
            for k in 0..6 {
                worst[k] = worst[k].max((a[k] - b[k]).abs());
            }
            stopped |= a[2] > 0.69;
        }
        stopped
    }

    #[test]
    fn a_fused_root_moves_as_its_chain_does() {
        fused_root_moves_as_its_chain_does("euler");
    }

    #[test]
    fn a_fused_root_moves_as_its_chain_does_with_implicit_velocity_terms() {
        fused_root_moves_as_its_chain_does("implicit");
    }

    fn fused_root_moves_as_its_chain_does(integrator: &str) {
        let (mut fused, mut chain) = (built(false, integrator), built(true, integrator));
        let mut worst = [0.0f32; 6];
        let stopped = step_both(&mut fused, &mut chain, &mut worst);
        let end = joint_state(&fused);
        assert!(stopped, "the bar reached its stop: {end:?}");
        assert!(end[1] < -0.01, "the spring sags under the bar: {end:?}");
        // Then each DOF's motor holds a target (mm, mm, deg) on its own axis.
        for world in [&mut fused, &mut chain] {
            world.set_command(ActionMode::Position, &[30.0, -5.0, -20.0]);
        }
        step_both(&mut fused, &mut chain, &mut worst);
        let held = joint_state(&fused);
        assert!((held[0] - 0.030).abs() < 1e-3, "x {held:?}");
        // Less the sag gravity leaves the PD: 0.3 N × 40 mm over 0.44 N·m/rad.
        assert!(
            (held[2] + 20f32.to_radians()).abs() < 0.05,
            "pitch {held:?}"
        );
        // Two 1 mg helpers (of 32 g) ride on the bar instead of the slides: positions
        // 1e-5 apart (m, rad); the stop's impact turns that into 5e-4 rad/s.
        assert!(
            worst[..3].iter().all(|&d| d < 2e-5),
            "positions apart by {worst:?}"
        );
        assert!(
            worst[3..].iter().all(|&d| d < 2e-3),
            "velocities apart by {worst:?}"
        );
    }

    #[test]
    fn a_fused_roots_helpers_read_out_where_the_chain_holds_them() {
        let (fused, chain) = both_after(120);
        let q = joint_state(&fused);
        assert!(q[1].abs() > 0.005 && q[2].abs() > 0.1, "moved: {q:?}");
        for h in [1, 2] {
            let (a, b) = (fused.body_pose(Units::Si, h), chain.body_pose(Units::Si, h));
            assert!(
                a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-5),
                "{h}: {a:?} {b:?}"
            );
            // It does not turn with the bar.
            assert!((a[3] - 1.0).abs() < 1e-6, "{a:?}");
            let (a, b) = (
                fused.group_velocity(&[h], [0.0; 3]),
                chain.group_velocity(&[h], [0.0; 3]),
            );
            assert!(
                a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-4),
                "{h}: {a:?} {b:?}"
            );
        }
        // The first helper follows x alone, the second x and z.
        let p1 = fused.point_position(Units::Si, 1, [0.0; 3]);
        let p2 = fused.point_position(Units::Si, 2, [0.0; 3]);
        assert!((p1[0] - (0.050 + f64::from(q[0]))).abs() < 1e-6, "{p1:?}");
        assert!((p1[2] - 0.200).abs() < 1e-6, "{p1:?}");
        assert!((p2[2] - (0.200 + f64::from(q[1]))).abs() < 1e-6, "{p2:?}");
        // The joints are drawn where the chain's are (all three anchored at one point).
        for (a, b) in fused.scene_joints().iter().zip(chain.scene_joints()) {
            let near = |x: [f32; 3], y: [f32; 3], tol: f32| {
                x.iter().zip(y).all(|(p, q)| (p - q).abs() < tol)
            };
            assert!(
                near(a.anchor, b.anchor, 1e-2) && near(a.axis, b.axis, 1e-6),
                "{a:?} {b:?}"
            );
        }
        let drawn: Vec<_> = fused
            .scene_parts()
            .into_iter()
            .filter(|p| p.instance == 2)
            .collect();
        let centre = drawn[0].position;
        assert!(
            (f64::from(centre[2]) - p2[2] * 1000.0).abs() < 1e-3,
            "{centre:?} {p2:?}"
        );
    }

    #[test]
    fn a_fused_roots_state_is_saved_as_the_chains_and_restores_its_bits() {
        let (mut fused, chain) = both_after(60);
        let (saved, theirs) = (fused.dynamic_state(), chain.dynamic_state());
        for (a, b) in saved.joints.iter().zip(&theirs.joints) {
            let nonzero = |c: &[f32; 6]| c.map(|v| v != 0.0);
            assert_eq!(nonzero(&a.coords), nonzero(&b.coords), "{a:?} {b:?}");
            assert!(a
                .coords
                .iter()
                .zip(b.coords)
                .all(|(x, y)| (x - y).abs() < 1e-5));
        }
        let mut restored = built(false, "euler");
        restored.restore_dynamic_state(&saved);
        for _ in 0..60 {
            fused.step().unwrap();
            restored.step().unwrap();
            assert_eq!(joint_state(&fused), joint_state(&restored));
        }
    }
}
