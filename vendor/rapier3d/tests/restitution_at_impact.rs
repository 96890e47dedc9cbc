//! gymfleet patch 25 (see `PATCHES.md`): a bouncy contact bounces at the end of the substep in
//! which it first pushes, not at the end of the step.
//!
//! A ball 0.05 mm above the floor, falling at 0.3 m/s, meets it in the first of a step's five
//! substeps (each covers 0.25 mm). It must leave the floor in that same step and rise for the
//! four substeps left, at the speed it arrived with; bounced at the end of the step instead, it
//! would still sit on the floor when the step ends.

use rapier3d::prelude::*;

const RADIUS: Real = 0.02;
const DT: Real = 1.0 / 240.0;
const SUBSTEPS: usize = 5;

/// One step of a ball of restitution `e` (floor of restitution `e`) whose lowest point starts
/// `gap` above the floor at `speed` downward; returns (height of its lowest point, vertical
/// velocity) after the step.
fn one_step(e: Real, gap: Real, speed: Real) -> (Real, Real) {
    let mut bodies = RigidBodySet::new();
    let mut colliders = ColliderSet::new();
    let ground = bodies.insert(RigidBodyBuilder::fixed());
    colliders.insert_with_parent(
        ColliderBuilder::new(SharedShape::halfspace(Vector::Z)).restitution(e),
        ground,
        &mut bodies,
    );
    let ball = bodies.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(0.0, 0.0, RADIUS + gap))
            .linvel(Vector::new(0.0, 0.0, -speed)),
    );
    colliders.insert_with_parent(
        ColliderBuilder::ball(RADIUS).restitution(e),
        ball,
        &mut bodies,
    );

    let params = IntegrationParameters {
        dt: DT,
        num_solver_iterations: SUBSTEPS,
        ..IntegrationParameters::default()
    };
    let mut pipeline = PhysicsPipeline::new();
    let mut islands = IslandManager::new();
    let mut broad_phase = DefaultBroadPhase::new();
    let mut narrow_phase = NarrowPhase::new();
    let mut impulse_joints = ImpulseJointSet::new();
    let mut multibody_joints = MultibodyJointSet::new();
    let mut soft_bodies = SoftBodySet::new();
    let mut ccd = CCDSolver::new();
    pipeline.step(
        Vector::new(0.0, 0.0, -9.81),
        &params,
        &mut islands,
        &mut broad_phase,
        &mut narrow_phase,
        &mut bodies,
        &mut colliders,
        &mut impulse_joints,
        &mut multibody_joints,
        &mut soft_bodies,
        &mut ccd,
        &(),
        &(),
    );
    let body = &bodies[ball];
    (body.translation().z - RADIUS, body.linvel().z)
}

/// Drops the ball from `gap` above the floor at 0.3 m/s with e = 1, expecting it to bounce at
/// the end of the first substep, from height `bounce_at`, at the approach speed of substep
/// `impact_substep` (1-based); checks the step's end: the speed it leaves at and how high it
/// rose.
fn check_bounce(gap: Real, impact_substep: usize, bounce_at: Real) {
    let speed = 0.3;
    let g = 9.81;
    let h = DT / SUBSTEPS as Real;
    let (height, vz) = one_step(1.0, gap, speed);
    // It leaves at the approach speed of substep `impact_substep` (gravity's increment
    // included) from height `bounce_at`, and rises for the four substeps left, each taking one
    // substep of gravity off (semi-implicit Euler).
    let impact = speed + impact_substep as Real * g * h;
    let left = SUBSTEPS - 1;
    let leaves = impact - left as Real * g * h;
    assert!(
        (vz - leaves).abs() < 0.01 * leaves,
        "gap {gap}: leaves at {vz} m/s, expected {leaves}"
    );
    // Bounced at the end of the step, the ball would still be on the floor.
    let rise: Real = bounce_at
        + (1..=left)
            .map(|k| (impact - k as Real * g * h) * h)
            .sum::<Real>();
    assert!(
        (height - rise).abs() < 0.05 * rise,
        "gap {gap}: {:.4} mm above the floor after the step, expected {:.4} mm",
        height * 1.0e3,
        rise * 1.0e3
    );
}

/// The ball reaches the floor within the first substep (0.05 mm away, 0.257 mm covered): the
/// biased solve stops it there, and it leaves at the speed it met the floor with.
#[test]
fn a_ball_leaves_the_floor_in_the_substep_it_meets_it() {
    check_bounce(0.05e-3, 1, 0.0);
}

/// The ball is 0.3 mm away: the first substep takes it to 0.043 mm, and the relax pass, seeing
/// it would cross in the second, stops and bounces it there. It leaves at the approach speed of
/// that second substep (one more substep of gravity): the bounce that keeps what semi-implicit
/// Euler conserves, `v²/2 + g·z − g·h·v/2`; at the first substep's speed, a ball dropped at
/// 0.3 m/s came back to 0.945 of its height instead of 0.996.
#[test]
fn a_ball_that_would_cross_in_the_next_substep_bounces_at_its_speed_there() {
    let h = DT / SUBSTEPS as Real;
    let after_first = 0.3e-3 - (0.3 + 9.81 * h) * h;
    check_bounce(0.3e-3, 2, after_first);
}

#[test]
fn a_ball_without_restitution_stays_on_the_floor() {
    let (height, vz) = one_step(0.0, 0.05e-3, 0.3);
    assert!(vz.abs() < 0.01, "leaves at {vz} m/s");
    assert!(
        height.abs() < 0.05e-3,
        "{:.4} mm above the floor",
        height * 1.0e3
    );
}
