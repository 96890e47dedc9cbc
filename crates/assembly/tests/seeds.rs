//! The seed documents and a document using every *(ext)* field parse into the expected
//! SI assembly.

mod common;

use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};

use common::{base_doc, ok};
use gymfleet_assembly::{
    parse, DofKind, JointType, Material, Shape, DEFAULT_DENSITY, DEFAULT_FRICTION,
    DEFAULT_RESTITUTION,
};
use serde_json::json;

const PENDULUM: &str = include_str!("../../../models/pendulum.json");
const ARM2: &str = include_str!("../../../models/arm2.json");

fn assert_close(actual: &[f64], expected: &[f64]) {
    assert_eq!(actual.len(), expected.len());
    for (a, e) in actual.iter().zip(expected) {
        assert!((a - e).abs() < 1e-12, "{actual:?} != {expected:?}");
    }
}

#[test]
fn pendulum_seed_parses_in_si() {
    let a = parse(PENDULUM).expect("pendulum.json is valid");
    assert_eq!(a.instances.len(), 2);
    let grounded: Vec<bool> = a.instances.iter().map(|i| i.grounded).collect();
    assert_eq!(grounded, [true, false]);

    let (base, arm) = (&a.instances[0], &a.instances[1]);
    assert_eq!(base.name, "base");
    assert_eq!(
        base.shape,
        Shape::Cuboid {
            size: [0.02, 0.02, 0.005]
        }
    );
    assert_eq!(base.position, [0.0; 3]);
    assert_eq!(base.rotation, [0.0; 3]);
    assert_eq!(arm.name, "arm");
    assert_eq!(
        arm.shape,
        Shape::Cuboid {
            size: [0.004, 0.004, 0.04]
        }
    );
    assert_close(&arm.position, &[0.008, 0.008, 0.005]);
    assert_eq!(arm.material, Material::default());

    assert_eq!(a.joints.len(), 1);
    let j = &a.joints[0];
    assert_eq!(j.name, "arm", "a joint's name defaults to its child's");
    assert_eq!(j.kind, JointType::Revolute);
    assert_eq!((j.parent, j.child), (0, 1));
    assert_close(&j.anchor, &[0.01, 0.01, 0.005]);
    assert_eq!(j.axis, [0.0, 1.0, 0.0]);
    assert_eq!(j.limits, None);
    assert_eq!(j.damping, 0.0, "no hidden damping");
    assert_eq!(j.max_effort, None);
    assert_eq!(j.dof_kinds(), [DofKind::Angular]);
    assert_eq!((a.total_dof(), a.num_movable_joints()), (1, 1));
}

#[test]
fn arm2_seed_parses_in_si() {
    let a = parse(ARM2).expect("arm2.json is valid");
    let names: Vec<&str> = a.instances.iter().map(|i| i.name.as_str()).collect();
    assert_eq!(names, ["base", "upper", "forearm"]);
    let grounded: Vec<bool> = a.instances.iter().map(|i| i.grounded).collect();
    assert_eq!(grounded, [true, false, false]);
    assert_eq!(a.instance_index("forearm"), Some(2));
    assert_eq!(
        a.instance_index("Forearm"),
        None,
        "ids are instance names, not parts"
    );

    assert_eq!(
        a.instances[0].shape,
        Shape::Cylinder {
            radius: 0.015,
            height: 0.005
        }
    );
    assert_eq!(
        a.instances[1].shape,
        Shape::Cuboid {
            size: [0.004, 0.004, 0.03]
        }
    );
    assert_eq!(
        a.instances[2].shape,
        Shape::Cuboid {
            size: [0.003, 0.003, 0.025]
        }
    );
    assert_close(&a.instances[1].position, &[-0.002, -0.002, 0.005]);
    assert_close(&a.instances[2].position, &[-0.0015, -0.0015, 0.035]);

    let (j0, j1) = (&a.joints[0], &a.joints[1]);
    assert_eq!((j0.name.as_str(), j0.parent, j0.child), ("upper", 0, 1));
    assert_eq!((j1.name.as_str(), j1.parent, j1.child), ("forearm", 1, 2));
    assert_close(&j0.anchor, &[0.0, 0.0, 0.005]);
    assert_close(&j1.anchor, &[0.0, 0.0, 0.035]);
    assert_close(&j0.limits.expect("limits"), &[-FRAC_PI_2, FRAC_PI_2]);
    assert_close(&j1.limits.expect("limits"), &[-2.0 * PI / 3.0, 0.0]);
    assert_eq!((a.total_dof(), a.num_movable_joints()), (2, 2));
}

#[test]
fn every_ext_field_is_read() {
    let doc = json!({
        "materials": {
            "aluminium": { "density": 2700, "friction": 0.3, "restitution": 0.2 },
            "rubber": { "density": 1100, "friction": 1.2, "restitution": 0.9 },
            "steel": { "density": 7850 }
        },
        "parts": [
            { "name": "Base", "primitive": { "type": "cube", "size": { "x": 100, "y": 100, "z": 10 } },
              "material": "aluminium" },
            { "name": "Slider", "primitive": { "type": "cube", "size": { "x": 10, "y": 10, "z": 10 } },
              "material": "aluminium" },
            { "name": "Rod", "primitive": { "type": "cylinder", "radius": 2, "height": 50 } },
            { "name": "Ball", "primitive": { "type": "sphere", "radius": 5 }, "material": "steel" },
            { "name": "Tip", "primitive": { "type": "cube", "size": { "x": 1, "y": 1, "z": 1 } } }
        ],
        "assembly": {
            "instances": [
                { "part": "Base", "name": "base" },
                { "part": "Slider", "name": "slider", "material": "rubber",
                  "position": { "x": 0, "y": 0, "z": 10 }, "rotation": { "x": 90, "y": 0, "z": -45 } },
                { "part": "Rod", "name": "rod", "position": { "x": 5, "y": 5, "z": 20 } },
                { "part": "Ball", "name": "ball", "position": { "x": 5, "y": 5, "z": 75 } },
                { "part": "Tip", "name": "tip", "position": { "x": 5, "y": 5, "z": 80 } },
                { "part": "Tip", "name": "loose", "position": { "x": 50, "y": 50, "z": 50 } }
            ],
            "joints": [
                { "type": "prismatic", "name": "lift", "parent": "base", "child": "slider",
                  "anchor": { "x": 0, "y": 0, "z": 10 }, "axis": { "x": 0, "y": 0, "z": 2 },
                  "min": 0, "max": 100, "damping": 0.5, "max_effort": 20 },
                { "type": "cylindrical", "parent": "slider", "child": "rod",
                  "anchor": { "x": 5, "y": 5, "z": 20 }, "axis": { "x": 3, "y": 4, "z": 0 },
                  "damping": 0.1 },
                { "type": "ball", "parent": "rod", "child": "ball",
                  "anchor": { "x": 5, "y": 5, "z": 70 }, "max_effort": 2.5 },
                { "type": "fixed", "name": "weld", "parent": "ball", "child": "tip" }
            ]
        }
    });
    let a = ok(doc);
    assert_eq!(a.instances.len(), 6);
    let grounded: Vec<bool> = a.instances.iter().map(|i| i.grounded).collect();
    assert_eq!(grounded, [true, false, false, false, false, false]);

    // Materials: from the part, overridden by the instance, defaulted field by field.
    let aluminium = Material {
        density: 2700.0,
        friction: 0.3,
        restitution: 0.2,
        soft_contact: None,
    };
    let rubber = Material {
        density: 1100.0,
        friction: 1.2,
        restitution: 0.9,
        soft_contact: None,
    };
    let steel = Material {
        density: 7850.0,
        friction: DEFAULT_FRICTION,
        restitution: DEFAULT_RESTITUTION,
        soft_contact: None,
    };
    let materials: Vec<Material> = a.instances.iter().map(|i| i.material).collect();
    assert_eq!(
        materials,
        [
            aluminium,
            rubber,
            Material::default(),
            steel,
            Material::default(),
            Material::default()
        ]
    );
    assert_eq!(Material::default().density, DEFAULT_DENSITY);

    let slider = &a.instances[1];
    assert_close(&slider.rotation, &[FRAC_PI_2, 0.0, -FRAC_PI_4]);
    assert_close(&slider.position, &[0.0, 0.0, 0.01]);
    assert_eq!(
        a.instances[2].shape,
        Shape::Cylinder {
            radius: 0.002,
            height: 0.05
        }
    );
    assert_eq!(a.instances[3].shape, Shape::Sphere { radius: 0.005 });

    let names: Vec<&str> = a.joints.iter().map(|j| j.name.as_str()).collect();
    assert_eq!(names, ["lift", "rod", "ball", "weld"]);
    let kinds: Vec<JointType> = a.joints.iter().map(|j| j.kind).collect();
    use JointType::*;
    assert_eq!(kinds, [Prismatic, Cylindrical, Ball, Fixed]);

    let lift = &a.joints[0];
    assert_eq!(lift.axis, [0.0, 0.0, 1.0], "axis is normalised");
    assert_close(&lift.limits.expect("limits"), &[0.0, 0.1]);
    assert_eq!((lift.damping, lift.max_effort), (0.5, Some(20.0)));
    assert_eq!(lift.dof_kinds(), [DofKind::Linear]);

    let cyl = &a.joints[1];
    assert_close(&cyl.axis, &[0.6, 0.8, 0.0]);
    assert_eq!((cyl.limits, cyl.damping, cyl.max_effort), (None, 0.1, None));
    assert_eq!(cyl.dof_kinds(), [DofKind::Linear, DofKind::Angular]);

    let ball = &a.joints[2];
    assert_close(&ball.anchor, &[0.005, 0.005, 0.07]);
    assert_eq!((ball.damping, ball.max_effort), (0.0, Some(2.5)));
    assert_eq!(ball.dof_kinds(), [DofKind::Angular; 3]);

    assert_eq!((a.joints[3].parent, a.joints[3].child), (3, 4));
    assert!(a.joints[3].dof_kinds().is_empty());
    assert_eq!(a.total_dof(), 1 + 2 + 3);
    assert_eq!(a.num_movable_joints(), 3);
}

#[test]
fn optional_sections_default() {
    let mut doc = base_doc();
    doc["assembly"].as_object_mut().unwrap().remove("joints");
    let a = ok(doc);
    assert!(a.joints.is_empty());
    assert!(
        !a.instances[1].grounded,
        "an unjointed instance is a free body"
    );
    assert_eq!((a.total_dof(), a.num_movable_joints()), (0, 0));
}

#[test]
fn one_sided_limits_stay_open() {
    let mut doc = base_doc();
    doc["assembly"]["joints"][0]["min"] = json!(-45);
    let limits = ok(doc).joints[0].limits.expect("limits");
    assert!((limits[0] + FRAC_PI_4).abs() < 1e-12);
    assert_eq!(limits[1], f64::INFINITY);
}

#[test]
fn shapes_have_exact_volumes_and_centroids() {
    let cube = Shape::Cuboid {
        size: [0.02, 0.02, 0.005],
    };
    assert!((cube.volume() - 2e-6).abs() < 1e-18);
    assert_close(&cube.centroid(), &[0.01, 0.01, 0.0025]);
    assert_eq!(cube.min_extent(), 0.005);
    let cyl = Shape::Cylinder {
        radius: 0.015,
        height: 0.005,
    };
    assert!((cyl.volume() - PI * 0.015 * 0.015 * 0.005).abs() < 1e-18);
    assert_close(&cyl.centroid(), &[0.0, 0.0, 0.0025]);
    let sphere = Shape::Sphere { radius: 0.005 };
    assert!((sphere.volume() - 4.0 / 3.0 * PI * 1.25e-7).abs() < 1e-18);
    assert_eq!(sphere.centroid(), [0.0; 3]);
    assert_eq!(sphere.min_extent(), 0.01);
}
