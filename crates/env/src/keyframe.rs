//! Keyframes: the document's named initial states ([`gymfleet_assembly::Keyframe`]), which
//! a reset starts from before its noise, resolved against the env's DOFs.

use gymfleet_assembly::{Assembly, BaseKey, KeyControl};
use gymfleet_physics::JointDof;

use crate::error::{EnvError, Result};
use crate::RobotEnv;

/// A keyframe resolved against the env's DOFs.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct StartKey {
    pub(crate) name: String,
    /// `(DOF, offset)`: the DOF's position offset from its initial one, deg or mm.
    pub(crate) offsets: Vec<(usize, f64)>,
    /// `(DOF, velocity)`, deg/s or mm/s.
    pub(crate) velocities: Vec<(usize, f64)>,
    pub(crate) base: Option<BaseKey>,
    /// `(instance, start)` of the free bodies it moves.
    pub(crate) free_bodies: Vec<(usize, BaseKey)>,
    /// `(mocap index, pose)` of the mocap bodies it places.
    pub(crate) mocap: Vec<(usize, BaseKey)>,
    /// The command it holds: `(DOF, value)` of directly actuated joints, `(actuator,
    /// control)`, and `(actuator, activation)`.
    pub(crate) dof_values: Vec<(usize, f64)>,
    pub(crate) controls: Vec<(usize, f64)>,
    pub(crate) activations: Vec<(usize, f64)>,
}

/// The assembly's keyframes against `dofs` ([`gymfleet_physics::RobotWorld::dofs`]).
pub(crate) fn resolve(assembly: &Assembly, dofs: &[JointDof]) -> Vec<StartKey> {
    let dof_of = |joint: usize| dofs.iter().position(|d| d.joint == joint);
    let mocaps = assembly.mocap_bodies();
    assembly
        .keyframes
        .iter()
        .map(|key| StartKey {
            name: key.name.clone(),
            offsets: key
                .positions
                .iter()
                .filter_map(|&(j, value)| {
                    let k = dof_of(j)?;
                    Some((k, value - dofs[k].reference - dofs[k].initial))
                })
                .chain(key.balls.iter().flat_map(|&(j, rotation, _)| {
                    let first = dof_of(j);
                    (0..3).filter_map(move |i| Some((first? + i, rotation[i])))
                }))
                .collect(),
            velocities: key
                .velocities
                .iter()
                .filter_map(|&(j, value)| Some((dof_of(j)?, value)))
                .chain(key.balls.iter().flat_map(|&(j, _, spin)| {
                    let first = dof_of(j);
                    (0..3).filter_map(move |i| Some((first? + i, spin[i])))
                }))
                .collect(),
            base: key.base,
            free_bodies: key.free_bodies.clone(),
            mocap: key
                .mocap
                .iter()
                .filter_map(|(i, pose)| Some((mocaps.iter().position(|m| m == i)?, *pose)))
                .collect(),
            dof_values: key
                .controls
                .iter()
                .filter_map(|&(c, v)| match c {
                    KeyControl::Joint(j) => Some((dof_of(j)?, v)),
                    KeyControl::Actuator(_) => None,
                })
                .collect(),
            controls: key
                .controls
                .iter()
                .filter_map(|&(c, v)| match c {
                    KeyControl::Actuator(k) => Some((k, v)),
                    KeyControl::Joint(_) => None,
                })
                .collect(),
            activations: key.activations.clone(),
        })
        .collect()
}

impl RobotEnv {
    /// The document's keyframes, by name, in document order.
    pub fn keyframes(&self) -> Vec<&str> {
        self.keyframes.iter().map(|k| k.name.as_str()).collect()
    }

    /// The keyframe named `name`, by index.
    pub fn keyframe_index(&self, name: &str) -> Result<usize> {
        self.keyframes
            .iter()
            .position(|k| k.name == name)
            .ok_or_else(|| EnvError::UnknownKeyframe {
                name: gymfleet_assembly::quoted(name),
                known: if self.keyframes.is_empty() {
                    "the document has none".into()
                } else {
                    format!(
                        "the document's are {}",
                        gymfleet_assembly::quoted_list(&self.keyframes())
                    )
                },
            })
    }

    /// Resets to the keyframe named `keyframe` (`None`: the document's
    /// `initial_keyframe`, if any), then draws the reset's noise on top, as
    /// [`RobotEnv::reset_into`] does; an unknown name changes nothing.
    pub fn reset_to_into(
        &mut self,
        seed: Option<u64>,
        keyframe: Option<&str>,
        out: &mut [f32],
    ) -> Result<()> {
        let key = keyframe.map(|name| self.keyframe_index(name)).transpose()?;
        self.reset_keyed_into(seed, key, out);
        Ok(())
    }

    /// Puts keyframe `key`'s free and mocap bodies where it says, and holds its command
    /// and activations (after the world's reset).
    pub(crate) fn finish_key_start(&mut self, key: usize) {
        let keyframes = std::sync::Arc::clone(&self.keyframes);
        let key = &keyframes[key];
        for (instance, start) in &key.free_bodies {
            self.world.place_free_body(*instance, start);
        }
        for (k, pose) in &key.mocap {
            self.world.place_mocap(*k, pose);
        }
        self.world
            .hold_key_command(&key.dof_values, &key.controls, &key.activations);
    }

    /// The keyframe's offsets and velocities on top of the reset's draws, into the
    /// `keyed_*` scratch; a DOF a task's `reset_noise.set` or `choice` draws keeps its draw. Returns
    /// the keyframe's base, if any.
    pub(crate) fn key_start(&mut self, key: usize) -> Option<BaseKey> {
        let keyframes = std::sync::Arc::clone(&self.keyframes);
        let key = &keyframes[key];
        self.keyed_offsets.copy_from_slice(&self.offsets);
        self.keyed_velocities
            .copy_from_slice(&self.start_velocities);
        let drawn = |k: usize| {
            self.sets.iter().any(|s| s.dofs.contains(&k))
                || self
                    .choice
                    .as_ref()
                    .is_some_and(|c| c.choice.dofs.contains(&k))
        };
        for &(k, offset) in &key.offsets {
            if !drawn(k) {
                self.keyed_offsets[k] += offset;
            }
        }
        for &(k, velocity) in &key.velocities {
            if !drawn(k) {
                let kind = self.spec.dofs[k].kind;
                self.keyed_velocities[k] += self.units.from_document(kind, velocity);
            }
        }
        key.base
    }
}
