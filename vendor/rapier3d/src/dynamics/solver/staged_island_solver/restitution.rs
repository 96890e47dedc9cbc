//! The restitution stages (box2d-style: a bouncy point that pushed has its normal velocity
//! driven to `−restitution · approach velocity`).
//!
//! gymfleet patch 25 (see `PATCHES.md`): the rigid-body contacts bounce at the end of the
//! substep in which they first push, not once at the end of the step, so a body that meets the
//! floor early in a step leaves it in that step instead of resting on it for the rest of the
//! step. A point bounces once: the pass consumes its seed. Patch 39 does
//! the same for the multibody (generic) contacts, which upstream bounced after the last
//! substep.

use super::{SharedCtx, stage_batch};

/// Runs the restitution pass of group `group_index` after a substep's last solve: the
/// rigid-body contact chunks (colors, then the overflow on worker 0) and the multibody
/// (generic) contacts (worker 0) whose points pushed for the first time in that substep;
/// `inv_dt` is the substep's. Returns the updated stage ordinal. Every worker calls it at the
/// same stage site (see `StageSync`).
///
/// # Safety
/// The [`SharedCtx`] contract: constraints of a same color touch pairwise-disjoint bodies, and
/// the overflow and generic constraints are touched by worker 0 alone.
pub(super) unsafe fn restitution_pass(
    ctx: &SharedCtx,
    group_index: usize,
    worker_id: usize,
    mut stage: usize,
    inv_dt: crate::math::Real,
) -> usize {
    let group = &ctx.groups[group_index];
    let sync = ctx.sync;
    {
        for (_, color) in &ctx.color_ranges[group.colors.clone()] {
            let mut done = 0;
            while let Some(claimed) = sync.claim(
                stage,
                color,
                stage_batch(color.end - color.start, sync.num_workers),
                worker_id,
            ) {
                let claimed_len = claimed.len();
                for chunk_id in claimed {
                    // SAFETY: constraints of a same color touch pairwise-disjoint bodies.
                    unsafe { restitute_chunk(ctx, chunk_id, inv_dt) };
                }
                done += claimed_len;
            }
            // One completion flush per worker per stage (see the warmstart stages).
            sync.complete(stage, done, color.len());
            stage = sync.sync(stage, color.len());
        }
    }

    // Overflow and generic contacts, on worker 0 alone.
    if worker_id == 0 {
        {
            for chunk_id in group.overflow.clone() {
                unsafe { restitute_chunk(ctx, chunk_id, inv_dt) };
            }
            // Generic constraints exist only on the single-group path. gymfleet patch 39:
            // they bounce in the substep they push too (upstream: after the last substep).
            if ctx.groups.len() == 1 {
                let contacts = unsafe { &mut *ctx.contact_constraints };
                let vs = unsafe { &mut *ctx.velocity_solver };
                for (builder, c) in contacts
                    .generic_velocity_constraints_builder
                    .iter()
                    .zip(contacts.generic_velocity_constraints.iter_mut())
                {
                    builder.apply_restitution(
                        c,
                        &contacts.generic_jacobians,
                        &mut vs.solver_bodies,
                        &mut vs.generic_solver_vels,
                        &vs.solver_vels_increment,
                        &vs.generic_solver_vels_increment,
                        inv_dt,
                    );
                }
            }
        }
        sync.complete(stage, 1, 1);
    }
    sync.sync(stage, 1)
}

/// Bounces the points of rigid-body contact chunk `chunk_id` that pushed, and consumes their
/// seeds.
///
/// # Safety
/// No other worker touches the chunk's bodies during the call.
unsafe fn restitute_chunk(ctx: &SharedCtx, chunk_id: usize, inv_dt: crate::math::Real) {
    let increments = unsafe { &(*ctx.velocity_solver).solver_vels_increment };
    let solver_bodies = unsafe { &mut (*ctx.velocity_solver).solver_bodies };
    #[cfg(feature = "dim3")]
    if ctx.use_twist {
        let builder = unsafe { &*ctx.twist_builders.add(chunk_id) };
        builder.apply_restitution(
            unsafe { &mut *ctx.twist_constraints.add(chunk_id) },
            solver_bodies,
            increments,
            inv_dt,
        );
    }
    if !ctx.use_twist {
        let builder = unsafe { &*ctx.coulomb_builders.add(chunk_id) };
        builder.apply_restitution(
            unsafe { &mut *ctx.coulomb_constraints.add(chunk_id) },
            solver_bodies,
            increments,
            inv_dt,
        );
    }
}
