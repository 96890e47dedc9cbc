//! Building a [`RobotWorld`] from an [`Assembly`]: bodies, colliders, the multibody tree
//! (in stages, `build/stages.rs`).

use gymfleet_assembly::{Assembly, JointType};
use rapier3d::prelude::*;

use crate::colliders::instance_pose;
use crate::command::{Command, ResolvedGains};
use crate::error::{PhysicsError, Result};
use crate::world::{BaseValues, FreeRoot, JointDof, PipelineCell, RobotWorld, Sets, WorldOptions};

mod params;
mod planar;
mod rehang;
mod slots;
mod split;
mod stages;
mod trees;

use params::{compliant_contacts_possible, integration_parameters};
use stages::{build_trees, empty_sets, place_bodies, world_parts};

impl RobotWorld {
    /// Builds the world: one body per instance (the first fixed, the others dynamic),
    /// exact primitive colliders, and every joint as a link of a reduced-coordinate
    /// multibody. Joint damping is exactly the document's (Rapier's default is removed).
    /// Joints with a `springdamper` get the stiffness and damping it sizes from the world
    /// built once without them (`springdamper.rs`).
    pub fn new(assembly: &Assembly, options: &WorldOptions) -> Result<Self> {
        if assembly.joints.iter().any(|j| j.springdamper.is_some()) {
            let sized = Self::build(assembly, options)?.sized_springdampers(assembly);
            return Self::build(&sized, options);
        }
        Self::build(assembly, options)
    }

    fn build(assembly: &Assembly, options: &WorldOptions) -> Result<Self> {
        check_options(options)?;
        let mut sets = empty_sets();
        let placed = place_bodies(&mut sets, assembly);
        let trees = build_trees(&mut sets, assembly, &placed, options)?;
        let (bodies, colliders, placements) = (placed.bodies, placed.colliders, placed.placements);
        let (params, substep_params) = integration_parameters(assembly, options);
        let n_dofs = trees.dofs.len();
        let placed_on = (&bodies[..], &colliders[..], &placements[..]);
        let parts = world_parts(assembly, &mut sets, placed_on, &trees)?;
        let n_actuators = parts.actuators.len();
        let instance_poses: Vec<Pose> = assembly.instances.iter().map(instance_pose).collect();
        let mut world = RobotWorld {
            planar_helpers: planar::helpers(&placed.roots, &instance_poses),
            hot: Default::default(),
            contact_work_limit: 0,
            rollback: Default::default(),
            fluid: crate::world::FluidDrag::new(assembly, &bodies, &sets),
            contact_filter: parts.contact_filter,
            tendons: parts.tendons,
            terrains: crate::terrain::terrain_slots(assembly),
            actuators: parts.actuators,
            activations: vec![0.0; n_actuators],
            base: base_values(
                assembly,
                &colliders,
                &sets,
                &trees.dofs,
                placed.given.clone(),
            ),
            free_roots: free_roots(&sets, &bodies, &placed.owners),
            free_bodies: parts.free_bodies,
            mocaps: parts.mocaps,
            initial: std::sync::Arc::new(sets.clone()),
            live: sets,
            pipeline_params: params,
            substep_params,
            substeps: options.substeps,
            soft_contacts: compliant_contacts_possible(assembly),
            gravity: trees.gravity,
            bodies,
            colliders,
            placements,
            owners: placed.owners,
            shared: placed.shared,
            given_now: placed.given,
            own_props: Vec::new(),
            joints: trees.joints,
            dofs: trees.dofs,
            floating_base: assembly.floating_base,
            gains: ResolvedGains {
                ball_omega_cap: 0.2 / options.substep_dt(),
                overridden: trees.overridden,
            },
            has_ball_joints: assembly.joints.iter().any(|j| j.kind == JointType::Ball),
            command: Command {
                values: vec![0.0; n_dofs],
                controls: vec![0.0; n_actuators],
                ..Command::default()
            },
            pipeline: PipelineCell(PhysicsPipeline::new()),
            sensor_plan: Default::default(),
            motion: Vec::new(),
        };
        let dof_joints: Vec<usize> = world.dofs.iter().map(|d| d.joint).collect();
        world.sensor_plan = std::sync::Arc::new(crate::world::SensorPlan::new(
            assembly,
            &dof_joints,
            &world.owners,
        ));
        world.update_own_props();
        world.reset();
        Ok(world)
    }
}

/// What randomisation scales from: the document's masses, densities, frictions, damping
/// and gains.
fn base_values(
    assembly: &Assembly,
    colliders: &[ColliderHandle],
    sets: &Sets,
    dofs: &[JointDof],
    given: Vec<Option<MassProperties>>,
) -> BaseValues {
    BaseValues {
        given,
        density: colliders
            .iter()
            .map(|&c| sets.colliders.get(c).map_or(0.0, |c| c.density()))
            .collect(),
        exact: assembly
            .instances
            .iter()
            .map(|i| {
                let density = if i.inertial.is_some() {
                    0.0
                } else {
                    i.material.density as Real
                };
                crate::colliders::exact_mass_properties(&i.shape, density)
            })
            .collect(),
        friction: colliders
            .iter()
            .map(|&c| sets.colliders.get(c).map_or(0.0, |c| c.friction()))
            .collect(),
        damping: assembly
            .joints
            .iter()
            .flat_map(|j| std::iter::repeat_n(j.damping as Real, j.observed_dof()))
            .collect(),
        kp: dofs.iter().map(|d| d.kp).collect(),
        kd: dofs.iter().map(|d| d.kd).collect(),
        kv: dofs.iter().map(|d| d.kv).collect(),
    }
}

/// `options.dt` in (0, 1] s and at least one substep.
fn check_options(options: &WorldOptions) -> Result<()> {
    let dt = options.dt;
    if !(dt.is_finite() && dt > 0.0 && dt <= 1.0) {
        return Err(PhysicsError::BadOption {
            field: "dt",
            reason: format!("expected a step length in (0, 1] s, got {dt}"),
        });
    }
    if options.substeps == 0 {
        return Err(PhysicsError::BadOption {
            field: "substeps",
            reason: "expected at least 1 substep, got 0".to_string(),
        });
    }
    Ok(())
}

/// The instances at the root of a tree with a dynamic root (a floating base, or a free
/// body that others are jointed to), in document order: each has six free coordinates
/// that no document joint owns.
fn free_roots(sets: &Sets, bodies: &[RigidBodyHandle], owners: &[usize]) -> Vec<FreeRoot> {
    bodies
        .iter()
        .enumerate()
        .filter(|&(i, &h)| owners[i] == i && sets.bodies[h].is_dynamic())
        .filter_map(|(instance, &h)| {
            let link = sets.multibody_joints.rigid_body_link(h)?;
            (link.id == 0).then_some(FreeRoot {
                instance,
                multibody: link.multibody,
            })
        })
        .collect()
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::{ActionMode, Units};

    /// The seed pendulum, tilted 10°, its arm's pivot 98 mm above the base (out of the
    /// base's reach as it swings); with `plate`, the arm hangs from a plate held there by
    /// a weld to the base instead of from the base itself (the plate touches neither:
    /// welded to one, jointed to the other).
    pub(crate) fn pendulum(plate: bool) -> Assembly {
        let (parent, plate_instance, weld) = if plate {
            (
                "plate",
                r#", { "part": "Plate", "name": "plate", "position": { "x": 0, "y": 0, "z": 100 } }"#,
                r#", { "type": "fixed", "parent": "base", "child": "plate",
                       "anchor": { "x": 10, "y": 10, "z": 103 } }"#,
            )
        } else {
            ("base", "", "")
        };
        let doc = format!(
            r#"{{
  "parts": [
    {{ "name": "Base", "primitive": {{ "type": "cube", "size": {{ "x": 20, "y": 20, "z": 5 }} }} }},
    {{ "name": "Arm", "primitive": {{ "type": "cube", "size": {{ "x": 4, "y": 4, "z": 40 }} }} }},
    {{ "name": "Plate", "primitive": {{ "type": "cube", "size": {{ "x": 20, "y": 20, "z": 3 }} }} }}
  ],
  "assembly": {{
    "instances": [
      {{ "part": "Base", "name": "base" }},
      {{ "part": "Arm", "name": "arm", "position": {{ "x": 8, "y": 8, "z": 103 }} }}{plate_instance}
    ],
    "joints": [
      {{ "type": "revolute", "parent": "{parent}", "child": "arm", "initial": 10,
         "anchor": {{ "x": 10, "y": 10, "z": 103 }}, "axis": {{ "x": 0, "y": 1, "z": 0 }} }}{weld}
    ]
  }}
}}"#
        );
        gymfleet_assembly::parse(&doc).unwrap()
    }

    fn swing(world: &mut RobotWorld, steps: usize) -> Vec<[f32; 2]> {
        world.set_command(ActionMode::Torque, &[0.0]);
        (0..steps)
            .map(|_| {
                world.step().unwrap();
                let (mut q, mut v) = ([0.0], [0.0]);
                world.joint_state(Units::Si, &mut q, &mut v);
                [q[0], v[0]]
            })
            .collect()
    }

    #[test]
    fn a_weld_to_the_ground_is_a_fixed_body_outside_the_tree_and_changes_no_motion() {
        let options = WorldOptions::default();
        let mut plain = RobotWorld::new(&pendulum(false), &options).unwrap();
        let mut welded = RobotWorld::new(&pendulum(true), &options).unwrap();

        // The plate is a fixed body, the fixed root of the arm's tree; the base is in no
        // tree. Two links, as the base's and the arm's are without the plate.
        let (base, plate) = (welded.bodies[0], welded.bodies[2]);
        assert!(welded.live.bodies[plate].is_fixed());
        let root = welded.live.multibody_joints.rigid_body_link(plate);
        assert_eq!(root.map(|l| l.id), Some(0));
        assert!(welded.live.multibody_joints.rigid_body_link(base).is_none());
        let links = |w: &RobotWorld| -> usize {
            w.live
                .multibody_joints
                .multibodies()
                .map(|mb| mb.num_links())
                .sum()
        };
        assert_eq!((links(&plain), links(&welded)), (2, 2));
        assert_eq!(welded.joints.len(), 2);
        assert_eq!(welded.dofs().len(), 1);

        // The arm falls from 10° exactly as it does hung from the base.
        let (a, b) = (swing(&mut plain, 300), swing(&mut welded, 300));
        assert!(a[299][0].abs() > 0.5, "the arm fell: {:?}", a[299]);
        for (k, (x, y)) in a.iter().zip(&b).enumerate() {
            assert!(
                (x[0] - y[0]).abs() < 1e-6 && (x[1] - y[1]).abs() < 1e-5,
                "step {k}: {x:?} against {y:?}"
            );
        }
    }
    /// The seed pendulum with an 8 mm cube welded on top of its arm.
    fn pendulum_with_a_tip() -> Assembly {
        let doc = r#"{
  "parts": [
    { "name": "Base", "primitive": { "type": "cube", "size": { "x": 20, "y": 20, "z": 5 } } },
    { "name": "Arm", "primitive": { "type": "cube", "size": { "x": 4, "y": 4, "z": 40 } } },
    { "name": "Tip", "primitive": { "type": "cube", "size": { "x": 8, "y": 8, "z": 8 } } }
  ],
  "assembly": {
    "instances": [
      { "part": "Base", "name": "base" },
      { "part": "Arm", "name": "arm", "position": { "x": 8, "y": 8, "z": 5 } },
      { "part": "Tip", "name": "tip", "position": { "x": 6, "y": 6, "z": 45 } }
    ],
    "joints": [
      { "type": "revolute", "parent": "base", "child": "arm", "initial": 10,
        "anchor": { "x": 10, "y": 10, "z": 5 }, "axis": { "x": 0, "y": 1, "z": 0 } },
      { "type": "fixed", "parent": "arm", "child": "tip",
        "anchor": { "x": 10, "y": 10, "z": 45 } }
    ]
  }
}"#;
        gymfleet_assembly::parse(doc).unwrap()
    }

    #[test]
    fn a_weld_to_a_moving_body_folds_the_instance_into_it() {
        let assembly = pendulum_with_a_tip();
        let mut world = RobotWorld::new(&assembly, &WorldOptions::default()).unwrap();
        // The tip rides on the arm's body with a collider of its own; no link for it.
        let (arm, tip) = (1, 2);
        assert_eq!(world.bodies[tip], world.bodies[arm]);
        assert_ne!(world.colliders[tip], world.colliders[arm]);
        assert_eq!(world.owners, [0, 1, 1]);
        let links: usize = world
            .live
            .multibody_joints
            .multibodies()
            .map(|mb| mb.num_links())
            .sum();
        assert_eq!(links, 2);
        assert_eq!((world.joints.len(), world.dofs().len()), (2, 1));

        // Each instance is still where it is, whole: the tip's own centre at its cube's
        // centre, turned 10° about the hinge with the arm; one scene part per instance.
        let turn = |p: [f64; 3]| {
            let (s, c) = 10f64.to_radians().sin_cos();
            let (x, z) = (p[0] - 10.0, p[2] - 5.0);
            [10.0 + c * x + s * z, p[1], 5.0 - s * x + c * z]
        };
        let close = |a: [f64; 3], b: [f64; 3]| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-3);
        let tip_centre = world.center_of_mass(Units::Document, tip);
        assert!(
            close(tip_centre, turn([10.0, 10.0, 49.0])),
            "{tip_centre:?}"
        );
        let arm_centre = world.center_of_mass(Units::Document, arm);
        assert!(
            close(arm_centre, turn([10.0, 10.0, 25.0])),
            "{arm_centre:?}"
        );
        let parts = world.scene_parts();
        assert_eq!(
            parts.iter().map(|p| p.instance).collect::<Vec<_>>(),
            [0, 1, 2]
        );

        // The body carries both masses once a step has applied them: the group's mass is
        // the body's, and the robot's centre of mass counts each instance once.
        world.step().unwrap();
        let volume = |mm: f64| (mm * 1e-3).powi(3);
        let density = assembly.instances[arm].material.density;
        let arm_mass = density * 4e-3 * 4e-3 * 40e-3;
        let tip_mass = density * volume(8.0);
        let body = world.live.bodies[world.bodies[arm]].mass();
        assert!(
            (f64::from(body) - (arm_mass + tip_mass)).abs() < 1e-9,
            "{body} kg"
        );
        let group = world.group_inertia(&[arm, tip], [0.0; 3]);
        assert!(
            (group[9] - (arm_mass + tip_mass)).abs() < 1e-9,
            "{}",
            group[9]
        );
        let robot = world.robot_center_of_mass(Units::Document);
        let (a, t) = (
            world.center_of_mass(Units::Document, arm),
            world.center_of_mass(Units::Document, tip),
        );
        let weighted: Vec<f64> = (0..3)
            .map(|k| (arm_mass * a[k] + tip_mass * t[k]) / (arm_mass + tip_mass))
            .collect();
        assert!(
            close(robot, [weighted[0], weighted[1], weighted[2]]),
            "{robot:?}"
        );
    }
    #[test]
    fn randomising_a_folded_instance_scales_its_own_mass_on_the_shared_body() {
        let assembly = pendulum_with_a_tip();
        let mut world = RobotWorld::new(&assembly, &WorldOptions::default()).unwrap();
        let (arm, tip) = (1, 2);
        let mut draws = crate::Draws::identity(3, 2);
        draws.mass = vec![1.0, 2.0, 3.0];
        world.apply_draws(&draws);
        let density = assembly.instances[arm].material.density;
        let (arm_mass, tip_mass) = (density * 4e-3 * 4e-3 * 40e-3, density * 8e-3_f64.powi(3));
        let body = f64::from(world.live.bodies[world.bodies[arm]].mass());
        assert!(
            (body - (2.0 * arm_mass + 3.0 * tip_mass)).abs() < 1e-9,
            "{body} kg"
        );
        // Each instance's own mass is its own share, scaled by its own factor.
        let tip_own = f64::from(world.own_mass_properties(tip).mass());
        assert!((tip_own - 3.0 * tip_mass).abs() < 1e-9, "{tip_own} kg");
        let group = world.group_inertia(&[tip], [0.0; 3]);
        assert!((group[9] - 3.0 * tip_mass).abs() < 1e-9, "{}", group[9]);
    }
}
