//! Actuators as MuJoCo computes them (`mj_fwdActuation`): for actuator `i` with length
//! `l` (gear × its joint's position, or × its tendon's length; SI, `reference` included)
//! and velocity `v`,
//!
//! `force = clamp(gain(l, v) · input + bias(l, v), force_range)`,
//!
//! the gain and the bias each `p₀ + p₁·l + p₂·v`, the input the control clamped into
//! `ctrl_range`, or the actuator's activation when it has dynamics. The joint (each of the
//! tendon's joints) gets `moment × force` as a generalized force, the moment `gear` (times
//! the tendon's coefficient). An activation follows `d act/dt = ctrl` (integrator) or
//! `(ctrl − act)/τ` (filter: an Euler step; filterexact: exact), clamped into `act_range`,
//! integrated after every substep with the force of the substep's start, as MuJoCo
//! integrates it after every step: with one substep per MuJoCo step the two agree; with
//! more, an integrator and an exact filter still do, and an Euler filter takes smaller
//! steps. An actuator whose force depends on the state (its length, velocity or
//! activation) makes the world recompute the efforts before every substep.

use gymfleet_assembly::{Assembly, Dynamics, Transmission};

use crate::world::{ActuatorSlot, JointSlot, RobotWorld, Sets};

/// The assembly's actuators over the world's DOFs, with each `dampratio` turned into a
/// velocity bias from the reflected inertia at the document's pose: `mass = Σ M₀[d] /
/// moment²` over the DOFs it moves (`M₀` the joint-space inertia's diagonal, armature
/// included: MuJoCo's `dof_M0`), `bias[2] = −dampratio · 2 · √(kp · mass)`.
pub(crate) fn actuator_slots(
    assembly: &Assembly,
    joints: &[JointSlot],
    sets: &Sets,
) -> Vec<ActuatorSlot> {
    let mut diagonal = None;
    assembly
        .actuators
        .iter()
        .map(|a| {
            let spatial = match a.transmission {
                Transmission::Tendon(t) if assembly.tendons[t].is_spatial() => Some((t, a.gear)),
                _ => None,
            };
            let moments: Vec<(usize, f64)> = match a.transmission {
                _ if spatial.is_some() => Vec::new(),
                Transmission::Joint(j) => vec![(joints[j].first_dof, a.gear)],
                Transmission::Tendon(t) => assembly.tendons[t]
                    .joints
                    .iter()
                    .map(|&(j, coef)| (joints[j].first_dof, a.gear * coef))
                    .collect(),
            };
            let mut bias = a.bias;
            if let Some(ratio) = a.dampratio {
                let m0 = diagonal.get_or_insert_with(|| dof_mass_diagonal(joints, sets));
                let mass: f64 = moments
                    .iter()
                    .filter(|(_, m)| m * m > f64::from(f32::MIN_POSITIVE))
                    .map(|&(d, m)| m0[d] / (m * m))
                    .sum();
                bias[2] = -ratio * 2.0 * (a.gain[0] * mass).sqrt();
            }
            ActuatorSlot {
                moments,
                spatial,
                ctrl_range: a.ctrl_range,
                force_range: a.force_range,
                act_range: a.act_range,
                gain: a.gain,
                bias,
                dynamics: a.dynamics,
                // A spatial tendon's moment arms follow the path.
                state_dependent: a.depends_on_state() || spatial.is_some(),
            }
        })
        .collect()
}

/// Every DOF's joint-space inertia (the mass matrix's diagonal, armature included) at the
/// world's current pose, in DOF order (vendored Rapier patch 38). It is read from a copy
/// whose bodies carry their given mass properties now (Rapier applies an instance's
/// `inertial` at the first step, `colliders::set_given_masses`).
fn dof_mass_diagonal(joints: &[JointSlot], sets: &Sets) -> Vec<f64> {
    let mut sets = sets.clone();
    let handles: Vec<_> = sets.bodies.iter().map(|(h, _)| h).collect();
    for h in handles {
        if let Some(rb) = sets.bodies.get_mut(h) {
            rb.recompute_mass_properties_from_colliders(&sets.colliders);
        }
    }
    let n = joints
        .iter()
        .map(|s| s.first_dof + s.observed_dofs)
        .max()
        .unwrap_or(0);
    let mut out = vec![0.0; n];
    let mut per_multibody = std::collections::HashMap::new();
    for slot in joints.iter().filter(|s| s.closing.is_none()) {
        let Some(mb) = sets.multibody_joints.get_multibody_mut(slot.multibody) else {
            continue;
        };
        let diagonal = per_multibody
            .entry(slot.multibody)
            .or_insert_with(|| mb.dof_mass_diagonal(&sets.bodies));
        let Some(first) = mb.link(slot.link).map(|l| l.assembly_id()) else {
            continue;
        };
        for k in 0..slot.observed_dofs {
            out[slot.first_dof + k] = f64::from(diagonal[slot.link_dof(first, k)]);
        }
    }
    out
}

fn clamp(value: f64, range: Option<[f64; 2]>) -> f64 {
    match range {
        Some([lo, hi]) => value.clamp(lo, hi),
        None => value,
    }
}

impl RobotWorld {
    /// Number of actuators.
    pub fn num_actuators(&self) -> usize {
        self.actuators.len()
    }

    /// Actuator `k`'s length and velocity, SI (MuJoCo's `actuator_length`,
    /// `actuator_velocity`).
    pub fn actuator_state(&self, k: usize) -> (f64, f64) {
        match self.actuators[k].spatial {
            Some((t, gear)) => {
                let (length, rate) = self.tendon_state(t);
                (gear * length, gear * rate)
            }
            None => self.combined_state(&self.actuators[k].moments),
        }
    }

    /// Actuator `k`'s force now (N or N·m at its transmission's input; MuJoCo's
    /// `actuator_force`), from the state, the held control and its activation.
    pub fn actuator_force(&self, k: usize) -> f64 {
        let a = &self.actuators[k];
        let (length, velocity) = if a.state_dependent {
            self.actuator_state(k)
        } else {
            (0.0, 0.0)
        };
        let affine = |p: &[f64; 3]| p[0] + p[1] * length + p[2] * velocity;
        let input = match a.dynamics {
            Dynamics::None => clamp(f64::from(self.command.controls[k]), a.ctrl_range),
            _ => self.activations[k],
        };
        clamp(affine(&a.gain) * input + affine(&a.bias), a.force_range)
    }

    /// Actuator `k`'s activation (MuJoCo's `act`; 0 for an actuator without dynamics).
    pub fn actuator_activation(&self, k: usize) -> f64 {
        self.activations[k]
    }

    /// The generalized force every actuator applies to DOF `dof` now: Σ moment × force
    /// (the actuators' part of MuJoCo's `qfrc_actuator`).
    pub(crate) fn actuators_on_dof(&self, dof: usize) -> f64 {
        (0..self.actuators.len())
            .map(|k| {
                let moment: f64 = match self.actuators[k].spatial {
                    Some((t, gear)) => gear * self.path_moment(&self.tendons[t].path, dof),
                    None => self.actuators[k]
                        .moments
                        .iter()
                        .filter(|(d, _)| *d == dof)
                        .map(|(_, m)| m)
                        .sum(),
                };
                if moment == 0.0 {
                    0.0
                } else {
                    moment * self.actuator_force(k)
                }
            })
            .sum()
    }

    /// Adds every actuator's generalized forces to its DOFs (after
    /// [`RobotWorld::apply_efforts`] has written the commanded ones).
    pub(crate) fn apply_actuator_forces(&mut self) {
        for k in 0..self.actuators.len() {
            let force = self.actuator_force(k);
            if let Some((t, gear)) = self.actuators[k].spatial {
                self.add_tendon_force(t, gear * force);
                continue;
            }
            let moments = std::mem::take(&mut self.actuators[k].moments);
            self.add_combined_force(&moments, force);
            self.actuators[k].moments = moments;
        }
    }

    /// Whether some actuator's force changes within a step.
    pub(crate) fn has_state_dependent_actuators(&self) -> bool {
        self.actuators.iter().any(|a| a.state_dependent)
    }

    /// Holds a keyframe's command after a reset, until a step's action replaces it: each
    /// `(dof, value)` a directly actuated DOF's torque-mode value, each `(actuator, control)`
    /// an actuator's control (MuJoCo's `ctrl`); and sets each `(actuator, activation)`
    /// (MuJoCo's `act`), clamped to the actuator's activation range.
    pub fn hold_key_command(
        &mut self,
        dofs: &[(usize, f64)],
        controls: &[(usize, f64)],
        activations: &[(usize, f64)],
    ) {
        for &(k, v) in dofs {
            if let Some(slot) = self.command.values.get_mut(k) {
                *slot = v as f32;
            }
        }
        for &(k, v) in controls {
            if let Some(slot) = self.command.controls.get_mut(k) {
                *slot = v as f32;
            }
        }
        for &(k, v) in activations {
            if let Some(a) = self.actuators.get(k) {
                self.activations[k] = clamp(v, a.act_range);
            }
        }
    }

    /// Advances every activation by `h` seconds under the held controls (MuJoCo's
    /// `mj_nextActivation`).
    pub(crate) fn advance_activations(&mut self, h: f64) {
        for (k, a) in self.actuators.iter().enumerate() {
            let ctrl = clamp(f64::from(self.command.controls[k]), a.ctrl_range);
            let act = self.activations[k];
            let next = match a.dynamics {
                Dynamics::None => continue,
                Dynamics::Integrator => act + h * ctrl,
                Dynamics::Filter { timeconst } => act + h * (ctrl - act) / timeconst,
                Dynamics::FilterExact { timeconst } => {
                    act + (ctrl - act) * (1.0 - (-h / timeconst).exp())
                }
            };
            self.activations[k] = clamp(next, a.act_range);
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::WorldOptions;

    /// Three arms hanging side by side from a base (a multibody each), the middle one with
    /// an armature.
    fn three_arms() -> Assembly {
        arms("[]")
    }

    /// [`three_arms`], joints named after their arms, with `actuators` (JSON).
    fn arms(actuators: &str) -> Assembly {
        arms_with(&format!("\"actuators\": {actuators}"))
    }

    /// [`three_arms`] with `extra`, more of the assembly's keys (JSON: `"couplings": [...]`).
    pub(crate) fn arms_with(extra: &str) -> Assembly {
        let doc = r#"{
  "parts": [
    { "name": "Base", "primitive": { "type": "cube", "size": { "x": 200, "y": 20, "z": 5 } } },
    { "name": "Arm", "primitive": { "type": "cube", "size": { "x": 4, "y": 4, "z": 40 } } }
  ],
  "assembly": {
    "instances": [
      { "part": "Base", "name": "base" },
      { "part": "Arm", "name": "a", "position": { "x": 0, "y": 8, "z": 100 } },
      { "part": "Arm", "name": "b", "position": { "x": 50, "y": 8, "z": 100 } },
      { "part": "Arm", "name": "c", "position": { "x": 100, "y": 8, "z": 100 } }
    ],
    "joints": [
      { "type": "revolute", "name": "a", "parent": "base", "child": "a",
        "anchor": { "x": 2, "y": 10, "z": 100 }, "axis": { "x": 0, "y": 1, "z": 0 } },
      { "type": "revolute", "name": "b", "parent": "base", "child": "b", "armature": 1e-6,
        "anchor": { "x": 52, "y": 10, "z": 100 }, "axis": { "x": 0, "y": 1, "z": 0 } },
      { "type": "revolute", "name": "c", "parent": "base", "child": "c",
        "anchor": { "x": 102, "y": 10, "z": 100 }, "axis": { "x": 0, "y": 1, "z": 0 } }
    ],
    EXTRA
  }
}"#;
        gymfleet_assembly::parse(&doc.replace("EXTRA", extra)).unwrap()
    }

    /// Each DOF's diagonal entry is its own arm's inertia about its axis (an arm of
    /// 0.64 g, 4 × 4 × 40 mm, about an axis through its top's centre line), armature
    /// included; with siblings only, the mass matrix is diagonal, so each entry is also
    /// the inverse of the inverse's (what the default gains use).
    #[test]
    fn the_mass_diagonal_is_each_dofs_inertia_armature_included() {
        let world = RobotWorld::new(&three_arms(), &WorldOptions::default()).unwrap();
        let diagonal = dof_mass_diagonal(&world.joints, &world.initial);
        let arm = 0.64e-3 * ((0.04f64.powi(2) + 0.004f64.powi(2)) / 12.0 + 0.02f64.powi(2));
        let mut sets = (*world.initial).clone();
        for (k, extra) in [(0, 0.0), (1, 1e-6), (2, 0.0)] {
            assert!(
                (diagonal[k] - arm - extra).abs() < 1e-5 * arm,
                "{k}: {} against {}",
                diagonal[k],
                arm + extra
            );
            // Each arm is a multibody of its own (`build/split.rs`).
            let slot = &world.joints[k];
            let mb = sets
                .multibody_joints
                .get_multibody_mut(slot.multibody)
                .unwrap();
            let inverse = mb.dof_inverse_inertia(&sets.bodies);
            let link = mb.link(slot.link).unwrap().assembly_id();
            assert!((diagonal[k] * f64::from(inverse[link]) - 1.0).abs() < 1e-5);
        }
    }

    /// The three arms with a motor on `a` and an integrated-velocity servo on `b`.
    fn actuated_arms() -> RobotWorld {
        let assembly = arms(
            r#"[{"name": "m", "joint": "a"},
                {"name": "iv", "type": "intvelocity", "joint": "b", "act_range": [-0.5, 0.5]}]"#,
        );
        RobotWorld::new(&assembly, &WorldOptions::default()).unwrap()
    }

    fn refusal(world: &RobotWorld, state: &crate::DynamicState) -> (String, String) {
        match world.check_dynamic_state(state) {
            Err(crate::PhysicsError::BadState { path, reason }) => (path, reason),
            other => panic!("expected a refused state, got {other:?}"),
        }
    }

    #[test]
    fn a_state_with_wrong_controls_or_activations_is_refused_by_field() {
        let world = actuated_arms();
        let good = world.dynamic_state();
        assert!(world.check_dynamic_state(&good).is_ok());
        let mut s = good.clone();
        s.controls.pop();
        assert_eq!(
            refusal(&world, &s),
            (
                "world.controls".into(),
                "expected 2 controls (one per actuator), got 1".into()
            )
        );
        let mut s = good.clone();
        s.controls[1] = f32::NAN;
        assert_eq!(
            refusal(&world, &s),
            (
                "world.controls[1]".into(),
                format!("expected a finite value within ±{:e}, got NaN", f32::MAX)
            )
        );
        let mut s = good.clone();
        s.activations.push(0.0);
        assert_eq!(
            refusal(&world, &s),
            (
                "world.activations".into(),
                "expected 2 activations (one per actuator), got 3".into()
            )
        );
        let mut s = good.clone();
        s.activations[0] = 0.1;
        assert_eq!(
            refusal(&world, &s),
            (
                "world.activations[0]".into(),
                "actuator 0 has no activation dynamics: expected 0, got 0.1".into()
            )
        );
        let mut s = good.clone();
        s.activations[1] = 0.7;
        assert_eq!(
            refusal(&world, &s),
            (
                "world.activations[1]".into(),
                "0.7 is outside actuator 1's activation range [-0.5, 0.5]".into()
            )
        );
        let mut s = good;
        s.activations[1] = f64::INFINITY;
        assert!(refusal(&world, &s)
            .1
            .starts_with("expected a finite value within"));
    }
}
