//! Vendored Rapier patches 46 and 48: a collider's AABB is computed once per pose and reused at
//! that pose. The reused box must be the one a fresh computation gives, bit for bit, and a
//! new shape or pose must not see the old one. A hull of more than 64 vertices has the box
//! of its rotated local box (as MuJoCo's broad phase), which must contain the exact one.

use rapier3d::prelude::*;

/// A hull of many vertices (a tessellated sphere squashed along z), as STL meshes give.
fn hull(scale: Real) -> SharedShape {
    let mut points = Vec::new();
    for i in 0..24 {
        for j in 0..12 {
            let (a, b) = (i as Real * 0.2618, j as Real * 0.2618 + 0.1);
            points.push(Vector::new(a.cos() * b.sin(), a.sin() * b.sin(), 0.4 * b.cos()) * scale);
        }
    }
    SharedShape::convex_hull(&points).expect("a hull")
}

/// The box a collider with nothing kept computes at `co`'s shape and pose; it contains the
/// exact box of the hull.
fn fresh(co: &Collider) -> Aabb {
    let new = ColliderBuilder::new(co.shared_shape().clone())
        .position(*co.position())
        .build();
    let aabb = new.compute_collision_aabb(0.0);
    let exact = co.shape().compute_aabb(co.position());
    assert!(aabb.contains(&exact), "{aabb:?} does not contain {exact:?}");
    aabb
}

/// A world holding one dynamic body, spinning 1 m above the origin, with `shape` as its
/// collider.
fn spinning(shape: SharedShape) -> (PhysicsWorld, ColliderHandle) {
    let mut world = PhysicsWorld::new();
    let body = world.bodies.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(0.0, 0.0, 1.0))
            .angvel(Vector::new(1.0, 2.0, 0.5))
            .build(),
    );
    let handle = world.colliders.insert_with_parent(
        ColliderBuilder::new(shape).build(),
        body,
        &mut world.bodies,
    );
    (world, handle)
}

#[test]
fn a_hulls_kept_aabb_is_the_fresh_one_at_every_pose_and_shape() {
    let (mut world, handle) = spinning(hull(0.1));
    for _ in 0..5 {
        world.step();
        let co = &world.colliders[handle];
        assert_eq!(co.compute_collision_aabb(0.0), fresh(co));
    }
    // A new shape at the same pose: the kept box of the old one must not be used.
    world.colliders[handle].set_shape(hull(0.3));
    let co = &world.colliders[handle];
    assert_eq!(co.compute_collision_aabb(0.0), fresh(co));
    assert!(co.compute_collision_aabb(0.0).extents().x > 0.5);
    world.step();
    let co = &world.colliders[handle];
    assert_eq!(co.compute_collision_aabb(0.0), fresh(co));
    // Moved by hand (no step): the kept box is for the old pose.
    world.colliders[handle].set_position(Pose::from_translation(Vector::new(3.0, 0.0, 0.0)));
    let co = &world.colliders[handle];
    assert_eq!(co.compute_collision_aabb(0.0), fresh(co));
    assert!(co.compute_collision_aabb(0.0).mins.x > 2.0);
}

/// Patch 48 keeps every shape's box, not only a hull's: a spinning capsule's kept box is a
/// fresh computation's at every pose, and a move by hand forgets it.
#[test]
fn a_capsules_kept_aabb_is_the_fresh_one_at_every_pose() {
    let (mut world, handle) = spinning(SharedShape::capsule_z(0.3, 0.05));
    for _ in 0..5 {
        world.step();
        let co = &world.colliders[handle];
        assert_eq!(co.compute_collision_aabb(0.0), fresh(co));
    }
    world.colliders[handle].set_position(Pose::from_translation(Vector::new(3.0, 0.0, 0.0)));
    let co = &world.colliders[handle];
    assert_eq!(co.compute_collision_aabb(0.0), fresh(co));
    assert!(co.compute_collision_aabb(0.0).mins.x > 2.0);
}
