//! The Rapier pipeline's parameters a world steps with: its step and substeps, the contact
//! model's scale, the compliant solver's sweeps (vendored patches 43 and 44) and the loops'
//! Gauss–Seidel passes.
//!
//! The tuning (each value's reason is in the comments beside it below):
//!
//! - Tolerances use `length_unit`, the smallest part extent (`world.rs`, clamped to 0.1
//!   mm–1 m), so that a 4 mm part gets micrometre-scale slop rather than 5 mm.
//! - Contact softness's natural frequency is multiplied by 1/√length_unit, so a resting
//!   body sags relative to its size as Rapier tunes it for metres.
//! - Rapier's speed cap (400 length units per second, a hidden brake with millimetre parts)
//!   is lifted to an absolute 1e4 / length_unit.
//! - Subnormal floats are flushed to zero during a step (vendored patch 8).
//! - Compliant contacts or soft limits switch on `compliant_contacts`, swept up to
//!   `COMPLIANT_SWEEPS` (16) times per pass until a sweep changes the impulses by at most
//!   `COMPLIANT_TOLERANCE` (1e-4) of their size; the prediction distance covers the largest
//!   margin and gap.
//! - A world with kinematic loops runs `LOOP_PGS_ITERATIONS` (4) Gauss–Seidel passes per
//!   substep instead of Rapier's 1.

use gymfleet_assembly::{Assembly, MM_PER_M};
use rapier3d::prelude::*;

use crate::world::{length_unit, WorldOptions};

/// Gauss–Seidel passes per substep for a world with kinematic loops (Rapier's default, 1,
/// otherwise).
const LOOP_PGS_ITERATIONS: usize = 4;
/// At most this many Gauss–Seidel sweeps over the compliant contacts and limits per solver
/// pass (vendored patch 43): a box's four corners on one body couple through a regulariser
/// 20 times smaller than their effective mass, and one sweep per pass settled a resting box
/// 15 % off MuJoCo's trajectory at its fifth step; swept to convergence it stays within 2 %
/// throughout (`client/python/tests/test_soft_contacts.py`), and InvertedDoublePendulum's
/// cart meets its soft stop within a step of MuJoCo's (`test_suite.py`). The pyramid's
/// facets (patch 51) start from zero at every step: 16 sweeps left a resting box 7 % shallower
/// than MuJoCo's, 64 settle it (`bench/journal/2026-12-08-pyramid-facets.md`).
const COMPLIANT_SWEEPS: usize = 64;
/// A pass's sweeps stop once one changes the compliant impulses by at most this fraction
/// of their size. Against 8 sweeps always, HalfCheetah's step costs 8 % more instructions
/// than the rigid model's instead of 23 % (`bench/peer/suite_builds.py --before-rigid
/// --callgrind`); 1e-2 left a resting box 2 % off MuJoCo's trajectory at two of its 600
/// steps, and at 1e-3 HalfCheetah's drift under random actions left MuJoCo's spread
/// (`bench/journal/2026-12-07-soft-contacts.md`).
const COMPLIANT_TOLERANCE: Real = 1.0e-4;

/// The pipeline's parameters for a whole step, and for one substep.
pub(super) fn integration_parameters(
    assembly: &Assembly,
    options: &WorldOptions,
) -> (IntegrationParameters, IntegrationParameters) {
    // One step is one pipeline step whose solver substeps are the integration substeps:
    // collision detection runs once per step (contacts are speculative, so a contact
    // about to close within the step is still solved at every substep). Worlds with
    // MuJoCo's compliant contacts detect at every substep instead (`RobotWorld::step`).
    let mut params = IntegrationParameters {
        dt: options.dt as Real,
        length_unit: length_unit(assembly),
        num_solver_iterations: options.substeps as usize,
        // Near rest, products of tiny velocities are subnormal f32s, each operation on
        // which costs ~100 cycles: the seed 6-DOF arm stepped 1.3× slower at rest than
        // swinging. Flushed to zero, identically on every thread.
        flush_denormals: true,
        ..IntegrationParameters::default()
    };
    // Rapier caps body speed at 400 length units per second; with millimetre parts
    // that is a hidden brake. Keep only an absolute, physically meaningless cap.
    params.normalized_max_linear_velocity = 1.0e4 / params.length_unit;
    // Contact softness is a frequency, so a resting body sags by g/ω² whatever its
    // size: 0.3 mm at Rapier's defaults, 7 % of a 4 mm part. Scaling ω by
    // 1/√length_unit keeps the sag relative to the part as Rapier tunes it for metres.
    let stiffen = 1.0 / params.length_unit.sqrt();
    params.contact_softness.natural_frequency *= stiffen;
    params.static_contact_softness.natural_frequency *= stiffen;

    // Compliant contacts (MuJoCo's solref/solimp, vendored patch 43) need the solver to
    // read each row's velocity at its substep's start, and act from their margin on.
    let soft = assembly
        .instances
        .iter()
        .filter_map(|i| i.material.soft_contact);
    // A pair's detection distance is its two margins and gaps summed.
    let margin_m = 2.0 * soft.clone().map(|s| s.margin + s.gap).fold(0.0, f64::max) / MM_PER_M;
    // Compliant limits (patch 44) need the same: their rows read the substep's start too.
    params.compliant_contacts =
        soft.count() > 0 || assembly.joints.iter().any(|j| j.soft_limit.is_some());
    params.compliant_sweeps = COMPLIANT_SWEEPS;
    params.compliant_tolerance = COMPLIANT_TOLERANCE;
    params.normalized_prediction_distance = params
        .normalized_prediction_distance
        .max(margin_m as Real / params.length_unit);

    // A loop's constraint couples the bodies of a tree the multibody solves exactly; one
    // Gauss–Seidel pass per substep left a driven four-bar 0.025° off its closed form,
    // four leave it 0.003° off (`crates/env/tests/loops.rs`).
    if assembly.has_loops() {
        params.num_internal_pgs_iterations = LOOP_PGS_ITERATIONS;
    }
    let substep_params = IntegrationParameters {
        dt: options.substep_dt() as Real,
        num_solver_iterations: 1,
        ..params
    };
    (params, substep_params)
}

/// Whether some instance with MuJoCo's compliant contacts can touch another (MuJoCo's rule
/// on the collision bits, `a.group & b.mask` or `b.group & a.mask`, or an explicit pair):
/// only then are contacts detected at every substep (`RobotWorld::step`). Gymnasium's
/// InvertedPendulum, whose geoms all have `contype` 0, has none.
pub(super) fn compliant_contacts_possible(assembly: &Assembly) -> bool {
    let soft = |i: usize| assembly.instances[i].material.soft_contact.is_some();
    if assembly
        .contacts
        .pairs
        .iter()
        .any(|p| soft(p.a) || soft(p.b))
    {
        return true;
    }
    // How many instances carry each bit in their group and in their mask.
    let (mut groups, mut masks) = ([0usize; 32], [0usize; 32]);
    for inst in &assembly.instances {
        for b in 0..32 {
            groups[b] += (inst.collision.0 >> b & 1) as usize;
            masks[b] += (inst.collision.1 >> b & 1) as usize;
        }
    }
    // Another instance (not `inst` itself) has bit `b` in `counts`.
    let other = |counts: &[usize; 32], own: u32, b: usize| counts[b] > (own >> b & 1) as usize;
    (0..assembly.instances.len()).filter(|&i| soft(i)).any(|i| {
        let (group, mask) = assembly.instances[i].collision;
        (0..32).any(|b| {
            (group >> b & 1 == 1 && other(&masks, mask, b))
                || (mask >> b & 1 == 1 && other(&groups, group, b))
        })
    })
}

#[cfg(test)]
mod tests {
    use super::compliant_contacts_possible;

    /// A ball over a plane, the plane `soft` or not, with the ball's and the plane's
    /// collision bits (group, mask).
    fn doc(soft: bool, ball: (u32, u32), plane: (u32, u32)) -> gymfleet_assembly::Assembly {
        let material = if soft {
            r#"{"soft_contact": {}}"#
        } else {
            "{}"
        };
        let doc = format!(
            r#"{{"parts": [
                {{"name": "Ground", "primitive": {{"type": "plane"}}, "material": "m"}},
                {{"name": "Ball", "primitive": {{"type": "sphere", "radius": 50}}}}],
              "materials": {{"m": {material}}},
              "assembly": {{"instances": [
                {{"part": "Ground", "name": "ground", "collision": {{"group": {}, "mask": {}}}}},
                {{"part": "Ball", "name": "ball", "position": {{"x": 0, "y": 0, "z": 60}},
                  "collision": {{"group": {}, "mask": {}}}}}]}}}}"#,
            plane.0, plane.1, ball.0, ball.1
        );
        gymfleet_assembly::parse(&doc).unwrap()
    }

    #[test]
    fn contacts_are_detected_every_substep_only_where_a_compliant_instance_can_touch() {
        // MuJoCo's rule: a.group & b.mask or b.group & a.mask.
        assert!(compliant_contacts_possible(&doc(true, (1, 1), (1, 1))));
        assert!(compliant_contacts_possible(&doc(true, (1, 0), (0, 1))));
        assert!(compliant_contacts_possible(&doc(true, (0, 2), (2, 0))));
        // InvertedPendulum's geoms: contype 0, conaffinity 1 on both sides.
        assert!(!compliant_contacts_possible(&doc(true, (0, 1), (0, 1))));
        // An instance's own bits do not count: the plane's group meets only its own mask.
        assert!(!compliant_contacts_possible(&doc(true, (0, 0), (1, 1))));
        // Rigid materials: detected once per step whatever the bits.
        assert!(!compliant_contacts_possible(&doc(false, (1, 1), (1, 1))));
    }
}
