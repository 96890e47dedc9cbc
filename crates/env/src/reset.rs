//! Resets: the initial state (or a keyframe's), then the episode's draws on top.

use gymfleet_assembly::BaseKey;
use gymfleet_physics::{ActionMode, Units};
use rand::rngs::Xoshiro256PlusPlus;
use rand::SeedableRng;

use crate::env::draw;
use crate::observation::Observation;
use crate::terms::{rotation_matrix, turn_about, Coord, Dist, Place};
use crate::RobotEnv;
use gymfleet_assembly::DofKind;

/// Starts drawn before one with no overlapping colliders is kept (dm_control's finger
/// gives up after 1000).
const MAX_START_DRAWS: usize = 1000;

impl RobotEnv {
    /// Restores the initial state (zero velocities) and returns the first observation.
    /// `seed` replaces the episode seed and restarts the random stream when given. With
    /// [`EnvConfig::reset_noise`] 0 the state is exactly the initial one; otherwise each
    /// DOF starts at an offset drawn from the stream, so the same seed gives the same
    /// start.
    pub fn reset(&mut self, seed: Option<u64>) -> Observation {
        let mut flat = vec![0.0; self.spec.observation_dim];
        self.reset_into(seed, &mut flat);
        self.structured(&flat)
    }

    /// [`RobotEnv::reset`], writing the flat observation into `out`
    /// (`observation_dim` floats).
    pub fn reset_into(&mut self, seed: Option<u64>, out: &mut [f32]) {
        self.reset_keyed_into(seed, None, out);
    }

    /// [`RobotEnv::reset_into`] from keyframe `key` (by index; `None`: the document's
    /// `initial_keyframe`, if any): the keyframe's positions, velocities and base, then
    /// the noise on top.
    ///
    /// # Panics
    ///
    /// If `key` is not an index of [`RobotEnv::keyframes`].
    pub fn reset_keyed_into(&mut self, seed: Option<u64>, key: Option<usize>, out: &mut [f32]) {
        if let Some(seed) = seed {
            self.seed = seed;
            self.rng = Xoshiro256PlusPlus::seed_from_u64(seed);
        }
        let key = key.or(self.initial_keyframe);
        if let Some(choice) = &mut self.choice {
            choice.start();
        }
        for _ in 0..if self.reject_contacts {
            MAX_START_DRAWS
        } else {
            1
        } {
            self.draw_start();
            self.place_start(key);
            if self.place_at_frame() {
                // The chosen frame was read from this placement: place again with it.
                self.place_start(key);
            }
            if !self.reject_contacts || !self.world.penetrating() {
                break;
            }
        }
        self.settle();
        if let Some(task) = &mut self.task {
            task.reset(&mut self.rng);
        }
        self.elapsed = 0;
        self.diverged = false;
        self.observe_into(out);
        self.start_task(out);
        self.observe_task_into(out);
        self.last_obs.copy_from_slice(out);
    }

    /// The episode's draws from the stream: offsets, velocities, the base's noise and
    /// orientation, the sets, the domain randomisation.
    fn draw_start(&mut self) {
        if let Some((dist, units)) = self.position_noise {
            for (offset, dof) in self.offsets.iter_mut().zip(&self.spec.dofs) {
                *offset = units.to_document(dof.kind, dist.draw(&mut self.rng));
            }
        }
        if let Some(dist) = self.velocity_noise {
            for v in &mut self.start_velocities {
                *v = dist.draw(&mut self.rng);
            }
        }
        if let Some((position, velocity)) = self.base_noise {
            let (poses, speeds) = self.base_draws.split_at_mut(7);
            for (values, dist) in [(poses, position), (speeds, velocity)] {
                for v in values.iter_mut() {
                    *v = dist.map_or(0.0, |d| d.draw(&mut self.rng));
                }
            }
        }
        let mut drawn = [0.0; crate::terms::MAX_TERMS];
        for set in &self.sets {
            let values = &mut drawn[..set.dofs.len()];
            set.draw(&mut self.rng, values);
            for (&k, &value) in set.dofs.iter().zip(values.iter()) {
                let dof = &self.spec.dofs[k];
                // Drawn as observed (with the reference); offsets are from the start.
                self.offsets[k] =
                    self.units.to_document(dof.kind, value) - dof.reference - dof.initial;
                if set.at_rest {
                    self.start_velocities[k] = 0.0;
                }
            }
        }
        if let Some(choice) = &mut self.choice {
            choice.draw(&mut self.rng);
            if choice.frame().is_none() {
                let values = choice.positions.clone();
                self.place_choice(&values);
            }
        }
        for &(a, b) in &self.equal {
            let (da, db) = (&self.spec.dofs[a], &self.spec.dofs[b]);
            // As observed: b's drawn position, then a's offset from its own start.
            let observed = self.offsets[b] + db.reference + db.initial;
            self.offsets[a] = observed - da.reference - da.initial;
            self.start_velocities[a] = self.start_velocities[b];
        }
        if let Some(r) = &self.randomize {
            let draws = draw(
                &mut self.rng,
                r,
                self.world.num_bodies(),
                self.world.num_joints(),
            );
            self.draws = Some(draws);
        }
        if self.turn_base {
            let q: [f64; 4] = std::array::from_fn(|_| Dist::Normal(1.0).draw(&mut self.rng));
            self.base_turn = Some(q);
        }
        for (draw, start) in self.mocap_draws.iter().zip(&mut self.mocap_starts) {
            *start = draw.draw(&mut self.rng);
        }
    }

    /// The choice's joints at `values` (as observed, the env's units), with its drawn
    /// velocities.
    fn place_choice(&mut self, values: &[f64]) {
        let Some(choice) = &self.choice else { return };
        for (j, &k) in choice.choice.dofs.iter().enumerate() {
            let dof = &self.spec.dofs[k];
            self.offsets[k] =
                self.units.to_document(dof.kind, values[j]) - dof.reference - dof.initial;
            self.start_velocities[k] = choice.velocities[j];
        }
    }

    /// With a frame option chosen: reads the frame's pose from the world as just placed
    /// and puts the choice's joints there. Returns whether it did (the world must then be
    /// placed again).
    fn place_at_frame(&mut self) -> bool {
        let Some(Place::Frame {
            body,
            point,
            rotation,
            from,
            offset,
        }) = self.choice.as_ref().and_then(|c| c.frame())
        else {
            return false;
        };
        let pose = self.world.site_pose(self.units, *body, *point, *rotation);
        let m = rotation_matrix([pose[3], pose[4], pose[5], pose[6]].map(f64::from));
        let values: Vec<f64> = from
            .iter()
            .zip(offset)
            .map(|(coord, o)| {
                o + match *coord {
                    Coord::Position(i) => f64::from(pose[i]),
                    Coord::Angle(i) => self
                        .units
                        .from_document(DofKind::Angular, turn_about(&m, i).to_degrees()),
                }
            })
            .collect();
        self.place_choice(&values);
        true
    }

    /// The initial state (or keyframe `key`'s) with the draws on top.
    fn place_start(&mut self, key: Option<usize>) {
        let base = key.and_then(|k| self.key_start(k));
        self.world.reset();
        if let Some(draws) = &self.draws {
            self.world.apply_draws(draws);
        }
        if let Some(base) = &base {
            self.world.place_base(base);
        }
        if let Some(k) = key {
            self.finish_key_start(k);
        }
        let (offsets, velocities) = match key {
            Some(_) => (&self.keyed_offsets, &self.keyed_velocities),
            None => (&self.offsets, &self.start_velocities),
        };
        let drawn = self.choice.is_some() || !self.equal.is_empty();
        if self.position_noise.is_some() || !self.sets.is_empty() || key.is_some() || drawn {
            self.world.offset_dofs(offsets);
        }
        if self.velocity_noise.is_some() || key.is_some() || drawn {
            self.world.set_dof_velocities(self.units, velocities);
        }
        if self.base_noise.is_some() {
            self.world.perturb_base(&self.base_draws, base.as_ref());
        }
        if let Some(q) = self.base_turn {
            self.world.turn_base(q);
        }
        for (draw, (start, turn)) in self.mocap_draws.iter().zip(&self.mocap_starts) {
            let now = self.world.mocap_pose(Units::Si, draw.mocap);
            self.world.place_mocap(
                draw.mocap,
                &BaseKey {
                    position: *start,
                    orientation: turn.unwrap_or([now[3], now[4], now[5], now[6]].map(f64::from)),
                    linear_velocity: [0.0; 3],
                    angular_velocity: [0.0; 3],
                },
            );
        }
    }

    /// The task's settling steps with a zero action (dm_control's cheetah falls onto its
    /// feet for 200 physics steps before the episode starts); a step stopped by the
    /// contact-work limit ends them early.
    fn settle(&mut self) {
        if self.settle_steps == 0 {
            return;
        }
        let zeros = vec![0.0; self.spec.action_dim];
        self.world.set_command(ActionMode::Torque, &zeros);
        for _ in 0..self.settle_steps {
            if self.world.step().is_err() {
                break;
            }
        }
    }
}
