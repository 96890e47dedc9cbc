//! `<keyframe><key>`: MuJoCo's named states (`qpos`, `qvel` in its qpos and qvel layouts)
//! become the document's keyframes. The joints' values are the observed positions
//! (MuJoCo's qpos, deg or mm); the floating base's free joint gives its body frame's pose,
//! which becomes its instance's.

use gymfleet_assembly::{BaseKeyDef, KeyframeDef};

use super::*;

/// What one joint of MuJoCo's model takes of its qpos and qvel, in qpos order (bodies in
/// tree order, each body's joints in order).
#[derive(Debug, Clone)]
pub(super) enum QposSlot {
    /// A hinge (radians in qpos) or a slide (m).
    Joint { name: String, prismatic: bool },
    /// A ball joint: a quaternion, and an angular velocity.
    Ball { name: String },
    /// A free joint: the body frame's position and quaternion, and its velocity. `base`:
    /// the floating base, whose instance `instance` lies at `frame` (world, m) when the
    /// body frame is at `body` (MuJoCo's qpos0).
    Free {
        base: bool,
        instance: String,
        body: Frame,
        frame: Frame,
    },
}

impl QposSlot {
    fn sizes(&self) -> (usize, usize) {
        match self {
            QposSlot::Joint { .. } => (1, 1),
            QposSlot::Ball { .. } => (4, 3),
            QposSlot::Free { .. } => (7, 6),
        }
    }
}

/// Farthest a value not applied may be from the model's default before a warning says so.
const UNAPPLIED_TOLERANCE: f64 = 1e-9;

impl<'a, 'i> Converter<'a, 'i> {
    /// Every `<key>` of the `<keyframe>` elements, in order; an unnamed one is `key<index>`
    /// (MuJoCo addresses it by index).
    pub(super) fn keyframe_defs(&mut self) -> Result<Vec<KeyframeDef>> {
        let root = self.doc.root_element();
        let keys: Vec<Node<'a, 'i>> = elements(root)
            .filter(|n| n.tag_name().name() == "keyframe")
            .flat_map(elements)
            .collect();
        let mut names = Names::default();
        let mut out = Vec::with_capacity(keys.len());
        for (index, key) in keys.into_iter().enumerate() {
            if key.tag_name().name() != "key" {
                self.warn(key, "ignored (a <keyframe> holds <key> elements)".into());
                continue;
            }
            let name = key
                .attribute("name")
                .filter(|n| !n.is_empty())
                .map_or_else(|| format!("key{index}"), str::to_string);
            let name = names.unique(&name);
            out.push(self.keyframe(key, name)?);
        }
        Ok(out)
    }

    fn keyframe(&mut self, key: Node<'a, 'i>, name: String) -> Result<KeyframeDef> {
        let (nq, nv) = self
            .qpos_slots
            .iter()
            .map(QposSlot::sizes)
            .fold((0, 0), |(q, v), (a, b)| (q + a, v + b));
        let qpos = self.sized(key, "qpos", nq)?;
        let qvel = self.sized(key, "qvel", nv)?;
        let mut def = KeyframeDef {
            name: name.clone(),
            time: self.number(key, None, "time")?.filter(|t| *t != 0.0),
            ..KeyframeDef::default()
        };
        self.key_mocap(key, &mut def)?;
        self.key_controls(key, &mut def)?;
        let (mut q, mut v) = (0, 0);
        let slots = self.qpos_slots.clone();
        for slot in &slots {
            let (dq, dv) = slot.sizes();
            let (qs, vs) = (
                &qpos.as_deref().map(|p| &p[q..q + dq]),
                &qvel.as_deref().map(|p| &p[v..v + dv]),
            );
            key_slot(&mut def, slot, *qs, *vs);
            q += dq;
            v += dv;
        }
        Ok(def)
    }

    /// A key's `mpos` and `mquat`: the mocap bodies' poses (MuJoCo's mocap order), each
    /// kept where it differs from the model's.
    fn key_mocap(&mut self, key: Node<'a, 'i>, def: &mut KeyframeDef) -> Result<()> {
        let n = self.mocap_bodies.len();
        let mpos = self.sized_as(key, "mpos", 3 * n, "3 per mocap body")?;
        let mquat = self.sized_as(key, "mquat", 4 * n, "4 per mocap body")?;
        for (k, (instance, body)) in self.mocap_bodies.iter().enumerate() {
            let mut p = frame_qpos(body);
            if let Some(m) = &mpos {
                p[..3].copy_from_slice(&m[3 * k..3 * k + 3]);
            }
            if let Some(m) = &mquat {
                p[3..].copy_from_slice(&m[4 * k..4 * k + 4]);
            }
            if !at_frame(&p, body) {
                def.mocap.insert(
                    instance.clone(),
                    BaseKeyDef {
                        position: Vec3::from([p[0], p[1], p[2]].map(|c| c * MM)),
                        orientation: [p[3], p[4], p[5], p[6]],
                        linear_velocity: None,
                        angular_velocity: None,
                    },
                );
            }
        }
        Ok(())
    }

    /// A key's `ctrl` (one per actuator) and `act` (one per actuator with an activation):
    /// the command and activations held at the reset, each kept where it is not 0.
    fn key_controls(&mut self, key: Node<'a, 'i>, def: &mut KeyframeDef) -> Result<()> {
        let actuators = self.key_actuators.clone();
        let with_act: Vec<&String> = actuators.iter().filter(|a| a.1).map(|a| &a.0).collect();
        let ctrl = self.sized_as(key, "ctrl", actuators.len(), "one per actuator")?;
        let act = self.sized_as(key, "act", with_act.len(), "one per actuator with dynamics")?;
        for ((name, _), v) in actuators.iter().zip(ctrl.unwrap_or_default()) {
            if v != 0.0 {
                def.controls.insert(name.clone(), v);
            }
        }
        for (name, v) in with_act.into_iter().zip(act.unwrap_or_default()) {
            if v != 0.0 {
                def.activations.insert(name.clone(), v);
            }
        }
        Ok(())
    }

    /// A key's `attribute` of exactly `n` numbers (`what` says which), if given.
    fn sized_as(
        &self,
        key: Node<'a, 'i>,
        attribute: &str,
        n: usize,
        what: &str,
    ) -> Result<Option<Vec<f64>>> {
        let values = self.numbers(key, None, attribute)?;
        if let Some(v) = values.as_ref().filter(|v| v.len() != n) {
            return Err(self.bad(
                key,
                attribute,
                format!("expected {n} numbers ({what}), got {}", v.len()),
            ));
        }
        Ok(values)
    }

    /// A key's `attribute` of exactly `n` numbers, if given (MuJoCo refuses another count).
    fn sized(&self, key: Node<'a, 'i>, attribute: &str, n: usize) -> Result<Option<Vec<f64>>> {
        let values = self.numbers(key, None, attribute)?;
        if let Some(v) = &values {
            if v.len() != n {
                return Err(self.bad(
                    key,
                    attribute,
                    format!(
                        "expected {n} numbers (the model's {}), got {}",
                        if attribute == "qpos" { "nq" } else { "nv" },
                        v.len()
                    ),
                ));
            }
        }
        Ok(values)
    }
}

/// A body frame as a free joint's qpos: position, then quaternion `[w, x, y, z]`.
fn frame_qpos(body: &Frame) -> Vec<f64> {
    let (t, q) = (body.translation, body.rotation);
    vec![t.x, t.y, t.z, q.w, q.x, q.y, q.z]
}

/// Whether a free joint's qpos (position, quaternion) is the body frame `body`.
fn at_frame(p: &[f64], body: &Frame) -> bool {
    let q = DQuat::from_xyzw(p[4], p[5], p[6], p[3]).normalize();
    (DVec3::new(p[0], p[1], p[2]) - body.translation).length() < UNAPPLIED_TOLERANCE
        && q.dot(body.rotation).abs() > 1.0 - UNAPPLIED_TOLERANCE
}

/// The floating base's keyframe from its free joint's qpos (body frame position, m, and
/// quaternion) and qvel (the body frame origin's velocity, world, and the angular
/// velocity in the body's frame): its instance's frame, which lies at `frame` when the
/// body frame is at `body`, and the instance origin's velocity. Without a qpos, the
/// model's pose; without a qvel, at rest.
fn base_key(qpos: &[f64], qvel: &[f64], body: &Frame, frame: &Frame) -> BaseKeyDef {
    let key = if qpos.len() == 7 {
        Frame {
            translation: DVec3::new(qpos[0], qpos[1], qpos[2]),
            rotation: DQuat::from_xyzw(qpos[4], qpos[5], qpos[6], qpos[3]).normalize(),
        }
    } else {
        *body
    };
    let local = Frame {
        translation: body.rotation.inverse() * (frame.translation - body.translation),
        rotation: (body.rotation.inverse() * frame.rotation).normalize(),
    };
    let instance = key.then(&local);
    let (linear, angular) = if qvel.len() == 6 {
        let omega = key.rotation * DVec3::new(qvel[3], qvel[4], qvel[5]);
        let origin = DVec3::new(qvel[0], qvel[1], qvel[2]);
        (
            origin + omega.cross(instance.translation - key.translation),
            omega,
        )
    } else {
        (DVec3::ZERO, DVec3::ZERO)
    };
    let q = instance.rotation;
    BaseKeyDef {
        position: vec3(instance.translation * MM),
        orientation: [q.w, q.x, q.y, q.z],
        linear_velocity: (linear != DVec3::ZERO).then(|| vec3(linear * MM)),
        angular_velocity: (angular != DVec3::ZERO)
            .then(|| vec3(angular * (180.0 / std::f64::consts::PI))),
    }
}

/// One joint's part of a key (`qs` its qpos, `vs` its qvel, where the key gives them) into
/// `def`, in the document's units: a hinge or slide's position and non-zero velocity, a
/// ball's turned rotation and spin, the floating base's pose and motion, a free body's
/// where it moved.
fn key_slot(def: &mut KeyframeDef, slot: &QposSlot, qs: Option<&[f64]>, vs: Option<&[f64]>) {
    match slot {
        QposSlot::Joint {
            name: joint,
            prismatic,
        } => {
            let unit = |x: f64| if *prismatic { x * MM } else { x.to_degrees() };
            if let Some(p) = qs {
                def.positions.insert(joint.clone(), unit(p[0]));
            }
            if let Some(w) = vs.filter(|w| w[0] != 0.0) {
                def.velocities.insert(joint.clone(), unit(w[0]));
            }
        }
        QposSlot::Ball { name: joint } => {
            let turned = qs.is_some_and(|p| {
                (p[0] - 1.0).abs() > UNAPPLIED_TOLERANCE
                    || p[1..].iter().any(|x| x.abs() > UNAPPLIED_TOLERANCE)
            });
            if let Some(p) = qs.filter(|_| turned) {
                def.rotations
                    .insert(joint.clone(), [p[0], p[1], p[2], p[3]]);
            }
            if let Some(w) = vs.filter(|w| w.iter().any(|x| *x != 0.0)) {
                let spin = [w[0], w[1], w[2]].map(f64::to_degrees);
                def.spins.insert(joint.clone(), Vec3::from(spin));
            }
        }
        QposSlot::Free {
            base: true,
            frame,
            body,
            ..
        } => {
            def.base = Some(base_key(qs.unwrap_or(&[]), vs.unwrap_or(&[]), body, frame));
        }
        QposSlot::Free { instance, body, .. } => {
            let moved = qs.is_some_and(|p| !at_frame(p, body))
                || vs.is_some_and(|w| w.iter().any(|x| *x != 0.0));
            if moved {
                // Its instance is its body frame: the key's qpos and qvel as observed.
                let p = qs.map_or_else(|| frame_qpos(body), <[f64]>::to_vec);
                let w = vs.map_or([0.0; 6].to_vec(), <[f64]>::to_vec);
                def.free_bodies.insert(
                    instance.clone(),
                    BaseKeyDef {
                        position: Vec3::from([p[0], p[1], p[2]].map(|c| c * MM)),
                        orientation: [p[3], p[4], p[5], p[6]],
                        linear_velocity: Some(Vec3::from([w[0], w[1], w[2]].map(|c| c * MM))),
                        angular_velocity: Some(Vec3::from([w[3], w[4], w[5]].map(f64::to_degrees))),
                    },
                );
            }
        }
    }
}
