//! Software prefetch of a world's state, for the batch stepper.
//!
//! A batch shard steps its envs one after another, so by the time an env's turn comes
//! round again the other envs have pushed its state out of the caches: past about 128
//! HalfCheetahs per core (each step reads some 47 KiB of an env's state) the step waits on
//! memory (BENCHMARKS.md, S6). [`RobotWorld::prefetch`] asks the processor to fetch the
//! memory the next step will read into the core's second-level cache, and the stepper calls
//! it for env `i + 1` before stepping env `i`, whose step is long enough for the loads to
//! land.
//!
//! The ranges (`world.rs`'s `HotRanges`) are the addresses of the Rapier sets' bodies,
//! colliders and their shapes, joints, multibody links, body jacobians and workspaces, contact
//! graph and manifolds, the solver's per-step buffers (vendored patch 37 lists the multibody
//! workspaces and the solver's buffers), and the world's own per-DOF tables. A world takes
//! them once something prefetches it: after its next step, and again every
//! [`REFRESH_EVERY`] steps (a set may have moved its storage since); a world nobody
//! prefetches (a single env, a batch below the threshold) never walks them. A stale range
//! costs a wasted hint, never a wrong result: a prefetch cannot fault and reads nothing the
//! program sees.

use core::mem::{size_of, size_of_val};
use core::sync::atomic::Ordering;

use rapier3d::geometry::PairContacts;

use crate::world::{HotRanges, RobotWorld};

/// Steps between two refreshes of a world's ranges.
const REFRESH_EVERY: u32 = 64;
/// The most cache lines one call prefetches (a bound on the hint's own cost).
const MAX_LINES: usize = 2048;
const LINE: usize = 64;

impl HotRanges {
    fn push_bytes(&mut self, start: usize, bytes: usize) {
        if bytes == 0 {
            return;
        }
        let first = start / LINE;
        let last = (start + bytes - 1) / LINE;
        self.ranges.push((first, last - first + 1));
    }

    fn push<T>(&mut self, value: &T) {
        self.push_bytes(core::ptr::from_ref(value).addr(), size_of::<T>());
    }

    fn push_slice<T>(&mut self, values: &[T]) {
        self.push_bytes(values.as_ptr().addr(), size_of_val(values));
    }

    /// Sorts and merges the ranges, and keeps at most [`MAX_LINES`] lines.
    fn finish(&mut self) {
        self.ranges.sort_unstable();
        let mut merged: Vec<(usize, usize)> = Vec::with_capacity(self.ranges.len());
        for &(first, lines) in &self.ranges {
            match merged.last_mut() {
                Some((start, len)) if first <= *start + *len => {
                    *len = (*len).max(first + lines - *start);
                }
                _ => merged.push((first, lines)),
            }
        }
        let mut budget = MAX_LINES;
        merged.retain_mut(|(_, lines)| {
            *lines = (*lines).min(budget);
            budget -= *lines;
            *lines > 0
        });
        self.ranges = merged;
    }
}

impl RobotWorld {
    /// Hints the processor to bring this world's state into the core's caches ahead of its
    /// next step (see the module documentation). Changes nothing the simulation reads; a
    /// no-op where the target has no prefetch instruction. The first call only marks the
    /// world: its next step takes the ranges, and later calls hint them.
    pub fn prefetch(&self) {
        self.hot.wanted.store(true, Ordering::Relaxed);
        for &(first, lines) in &self.hot.ranges {
            for line in first..first + lines {
                prefetch_line(line * LINE);
            }
        }
    }

    /// After a step of a world that is prefetched: takes the ranges again if they are missing
    /// or [`REFRESH_EVERY`] steps old. The state is in cache then, so walking it is cheap.
    /// Nothing for a world nobody prefetches (a single env, a batch below the threshold).
    pub(crate) fn age_hot_ranges(&mut self) {
        if !self.hot.wanted.load(Ordering::Relaxed) {
            return;
        }
        self.hot.age += 1;
        if self.hot.ranges.is_empty() || self.hot.age >= REFRESH_EVERY {
            self.refresh_hot_ranges();
        }
    }

    fn refresh_hot_ranges(&mut self) {
        let mut hot = core::mem::take(&mut self.hot);
        hot.ranges.clear();
        hot.age = 0;
        let s = &self.live;
        for (_, body) in s.bodies.iter() {
            hot.push(body);
        }
        for (_, collider) in s.colliders.iter() {
            hot.push(collider);
            let shape = collider.shape();
            hot.push_bytes(core::ptr::from_ref(shape).addr(), size_of_val(shape));
        }
        for (_, joint) in s.impulse_joints.iter() {
            hot.push(joint);
        }
        for multibody in s.multibody_joints.multibodies() {
            hot.push(multibody);
            for (i, link) in multibody.links().enumerate() {
                hot.push(link);
                hot.push_slice(multibody.body_jacobian(i).as_slice());
            }
            multibody.workspace_buffers(|address, bytes| hot.push_bytes(address, bytes));
        }
        self.pipeline
            .0
            .workspace_buffers(|address, bytes| hot.push_bytes(address, bytes));
        let graph = s.narrow_phase.contact_graph().raw_graph();
        hot.push_slice(graph.raw_nodes());
        hot.push_slice(graph.raw_edges());
        for pair in s.narrow_phase.contact_pairs() {
            hot.push(pair);
            if let PairContacts::Rigid(contacts) = &pair.contacts {
                hot.push_slice(&contacts.manifolds);
                for manifold in &contacts.manifolds {
                    hot.push_slice(&manifold.points);
                }
            }
        }
        hot.push_slice(&self.bodies);
        hot.push_slice(&self.joints);
        hot.push_slice(&self.dofs);
        hot.push_slice(&self.command.values);
        hot.finish();
        self.hot = hot;
    }
}

#[cfg(target_arch = "x86_64")]
#[allow(unsafe_code)]
fn prefetch_line(address: usize) {
    use core::arch::x86_64::{_mm_prefetch, _MM_HINT_T1};
    // SAFETY: `prefetch` is a hint. It never faults and changes no state the program can
    // observe, whatever the address; SSE is part of every x86-64 target.
    unsafe { _mm_prefetch::<_MM_HINT_T1>(core::ptr::without_provenance(address)) }
}

#[cfg(not(target_arch = "x86_64"))]
fn prefetch_line(_address: usize) {}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::build::tests::pendulum;
    use crate::{ActionMode, Units, WorldOptions};

    fn state(world: &RobotWorld) -> [u32; 2] {
        let (mut q, mut v) = ([0.0], [0.0]);
        world.joint_state(Units::Si, &mut q, &mut v);
        [q[0].to_bits(), v[0].to_bits()]
    }

    #[test]
    fn ranges_merge_in_address_order_within_the_line_budget() {
        let mut hot = HotRanges::default();
        hot.push_bytes(10 * LINE + 60, 8); // lines 10 and 11
        hot.push_bytes(3 * LINE, LINE); // line 3
        hot.push_bytes(12 * LINE, 1); // line 12, next to 10..=11
        hot.push_bytes(4 * LINE + 1, 0); // nothing
        hot.push_bytes(2 * LINE, 2 * LINE); // lines 2 and 3, overlapping line 3
        hot.finish();
        assert_eq!(hot.ranges, [(2, 2), (10, 3)]);

        let mut hot = HotRanges::default();
        hot.push_bytes(0, (MAX_LINES - 1) * LINE);
        hot.push_bytes((MAX_LINES + 10) * LINE, 5 * LINE);
        hot.push_bytes((MAX_LINES + 100) * LINE, LINE);
        hot.finish();
        assert_eq!(hot.ranges, [(0, MAX_LINES - 1), (MAX_LINES + 10, 1)]);
    }

    #[test]
    fn a_prefetched_world_takes_the_ranges_of_its_bodies_and_buffers_and_a_clone_or_reset_drops_them(
    ) {
        let mut world = RobotWorld::new(&pendulum(false), &WorldOptions::default()).unwrap();
        assert!(world.hot.ranges.is_empty());
        world.set_command(ActionMode::Torque, &[0.0]);
        // A world nobody prefetches takes no ranges.
        world.step().unwrap();
        assert!(world.hot.ranges.is_empty());
        world.prefetch();
        world.step().unwrap();
        let ranges = world.hot.ranges.clone();
        assert!(
            ranges.windows(2).all(|w| w[0].0 + w[0].1 < w[1].0),
            "{ranges:?}"
        );
        let covered = |address: usize| {
            let line = address / LINE;
            ranges
                .iter()
                .any(|&(first, n)| (first..first + n).contains(&line))
        };
        for (_, body) in world.live.bodies.iter() {
            let start = core::ptr::from_ref(body).addr();
            assert!(covered(start) && covered(start + size_of_val(body) - 1));
        }
        let mut buffers = Vec::new();
        world
            .pipeline
            .0
            .workspace_buffers(|a, n| buffers.push((a, n)));
        for multibody in world.live.multibody_joints.multibodies() {
            multibody.workspace_buffers(|a, n| buffers.push((a, n)));
        }
        assert!(buffers.len() > 10, "{buffers:?}");
        for (address, bytes) in buffers {
            assert!(covered(address) && covered(address + bytes - 1));
        }
        assert!(world.clone().hot.ranges.is_empty());
        world.reset();
        assert!(world.hot.ranges.is_empty());
        // A reset world is still prefetched: its next step takes the ranges again.
        world.step().unwrap();
        assert!(!world.hot.ranges.is_empty());
    }

    #[test]
    fn prefetching_changes_no_bit_of_the_trajectory() {
        let mut plain = RobotWorld::new(&pendulum(false), &WorldOptions::default()).unwrap();
        let mut hinted = plain.clone();
        for world in [&mut plain, &mut hinted] {
            world.set_command(ActionMode::Torque, &[0.0]);
        }
        for _ in 0..(REFRESH_EVERY as usize + 5) {
            hinted.prefetch();
            plain.step().unwrap();
            hinted.step().unwrap();
            assert_eq!(state(&plain), state(&hinted));
        }
        assert!(!hinted.hot.ranges.is_empty());
    }
}
