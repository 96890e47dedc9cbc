//! gymfleet patch 48: a pair of a half-space and a convex shape whose box lies farther above
//! the plane than the manifold's prediction distance ends its update without a manifold. It
//! must still land: a ball and a tilted capsule dropped onto a tilted plane come to rest on
//! it, with and without soft CCD, and the pair carried no contact points while they fell.

use rapier3d::prelude::*;

/// Drops `shape` from 1 m above a plane tilted by 0.3 rad onto it, for 2 s, and returns how
/// many steps its pair with the plane had a manifold point, how many steps it fell more than
/// 0.5 m above the plane with no manifold at all (culled), and its final height above it.
fn drop_onto_tilted_plane(
    shape: SharedShape,
    rotation: Vector,
    soft_ccd: bool,
) -> (usize, usize, Real) {
    let mut bodies = RigidBodySet::new();
    let mut colliders = ColliderSet::new();
    let normal = Rotation::from_scaled_axis(Vector::new(0.3, 0.0, 0.0)) * Vector::Z;
    let floor = colliders.insert(
        ColliderBuilder::new(SharedShape::halfspace(normal))
            .translation(Vector::new(0.5, -0.2, 0.1))
            .build(),
    );
    let start = Vector::new(0.5, -0.2, 0.1) + normal * 1.0;
    let mut builder = RigidBodyBuilder::dynamic()
        .translation(start)
        .rotation(rotation);
    if soft_ccd {
        builder = builder.soft_ccd_prediction(0.5);
    }
    let body = bodies.insert(builder.build());
    let dropped = colliders.insert_with_parent(
        ColliderBuilder::new(shape).friction(1.0).build(),
        body,
        &mut bodies,
    );
    let (mut islands, mut broad, mut narrow) = (
        IslandManager::new(),
        BroadPhaseBvh::new(),
        NarrowPhase::new(),
    );
    let (mut impulse, mut multibody) = (ImpulseJointSet::new(), MultibodyJointSet::new());
    let (mut soft, mut ccd) = (SoftBodySet::new(), CCDSolver::new());
    let mut pipeline = PhysicsPipeline::new();
    let params = IntegrationParameters::default();
    let height = |bodies: &RigidBodySet| {
        (bodies[body].translation() - Vector::new(0.5, -0.2, 0.1)).dot(normal)
    };
    let (mut with_points, mut culled_high) = (0, 0);
    for _ in 0..120 {
        pipeline.step(
            Vector::new(0.0, 0.0, -9.81),
            &params,
            &mut islands,
            &mut broad,
            &mut narrow,
            &mut bodies,
            &mut colliders,
            &mut impulse,
            &mut multibody,
            &mut soft,
            &mut ccd,
            &(),
            &(),
        );
        let pair = narrow
            .contact_pair(floor, dropped)
            .expect("a plane pairs with everything");
        let points: usize = pair.manifolds().iter().map(|m| m.points.len()).sum();
        if points > 0 {
            with_points += 1;
        }
        // Without the cull the contact dispatcher would have made the pair's manifold (an
        // empty one) at its first update.
        if pair.manifolds().is_empty() && height(&bodies) > 0.5 {
            culled_high += 1;
        }
    }
    (with_points, culled_high, height(&bodies))
}

#[test]
fn shapes_far_above_a_plane_carry_no_contact_points_and_still_land_on_it() {
    let capsule_rotation = Vector::new(0.0, 1.2, 0.4);
    for soft_ccd in [false, true] {
        let (with_points, culled_high, rest) =
            drop_onto_tilted_plane(SharedShape::ball(0.1), Vector::ZERO, soft_ccd);
        assert!(
            culled_high > 10,
            "soft CCD {soft_ccd}: {culled_high} steps culled while high"
        );
        assert!(
            with_points > 60,
            "soft CCD {soft_ccd}: landed for only {with_points} steps"
        );
        // At rest on its radius (the solver's slop aside).
        assert!(
            (rest - 0.1).abs() < 0.01,
            "soft CCD {soft_ccd}: ball rests at {rest}"
        );

        let (with_points, culled_high, rest) = drop_onto_tilted_plane(
            SharedShape::capsule_z(0.2, 0.05),
            capsule_rotation,
            soft_ccd,
        );
        assert!(
            culled_high > 10,
            "soft CCD {soft_ccd}: {culled_high} steps culled while high"
        );
        assert!(
            with_points > 60,
            "soft CCD {soft_ccd}: landed for only {with_points} steps"
        );
        // Lying on the plane: its axis parallel to it, its centre a radius above it.
        assert!(
            (rest - 0.05).abs() < 0.01,
            "soft CCD {soft_ccd}: capsule rests at {rest}"
        );
    }
}
