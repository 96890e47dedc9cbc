//! Sensors (`Assembly::sensors`) evaluated on the world's state: MuJoCo's `sensordata`,
//! SI, world frame unless the sensor's type says otherwise (`engine_sensor.c`).
//!
//! - Position and velocity sensors read the state now, as MuJoCo's do after `mj_forward`.
//! - Sensors that need accelerations (accelerometer, framelinacc, frameangacc, force,
//!   torque) take each body's velocity change over the last step, divided by `dt`; after a
//!   reset or a state put back, the accelerations are 0 (an accelerometer reads −gravity).
//! - Touch, force and torque read the last step's contact forces, as the task terms do
//!   (`contacts.rs`); zeros after a reset.
//! - Touch sums the normal forces of the contacts on the site's body (its instance and the
//!   instances welded to it) whose point is inside the site's volume, as MuJoCo's does; a
//!   site without a volume counts every contact on the body.

use gymfleet_assembly::SensorType;
use rapier3d::math::{Real, Rotation, Vector};
use rapier3d::prelude::{QueryFilter, Ray};

use crate::units::Units;
use crate::world::{RobotWorld, SensorFrame as Frame, SensorObject as Object, SensorReading};

type V3 = [f64; 3];

fn v3(v: Vector) -> V3 {
    [v.x, v.y, v.z].map(f64::from)
}
fn vec(v: V3) -> Vector {
    Vector::new(v[0] as Real, v[1] as Real, v[2] as Real)
}
fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn scale(a: V3, s: f64) -> V3 {
    a.map(|v| v * s)
}
fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
/// `v` expressed in the axes of `q`.
fn local(q: Rotation, v: V3) -> V3 {
    v3(q.inverse() * vec(v))
}

/// A body point's motion: position (m), velocity (m/s), angular velocity (rad/s) and,
/// when asked for, the point's acceleration and the angular acceleration.
struct Motion {
    p: V3,
    v: V3,
    w: V3,
}

impl RobotWorld {
    /// Floats the sensors report together (MuJoCo's `nsensordata`).
    pub fn sensor_dim(&self) -> usize {
        self.sensor_plan.dim
    }

    /// Writes every sensor's reading into `out` ([`RobotWorld::sensor_dim`] floats, the
    /// sensors in document order, each as many as its type reports), SI.
    pub fn sensor_data(&self, out: &mut [f64]) {
        let plan = &self.sensor_plan;
        let mut wrenches = Vec::new();
        let mut at = 0;
        for s in &plan.sensors {
            let n = s.kind.dim();
            let Some(slot) = out.get_mut(at..at + n) else {
                return;
            };
            at += n;
            self.read_sensor(s, plan.magnetic, &mut wrenches, slot);
            if s.cutoff > 0.0 {
                match s.kind.cutoff_kind() {
                    Some(true) => slot
                        .iter_mut()
                        .for_each(|v| *v = v.clamp(-s.cutoff, s.cutoff)),
                    Some(false) => slot.iter_mut().for_each(|v| *v = v.min(s.cutoff)),
                    None => {}
                }
            }
        }
    }

    /// Keeps each body's velocity before a step, for the sensors that read accelerations.
    pub(crate) fn keep_motion(&mut self) {
        if !self.sensor_plan.needs_motion {
            return;
        }
        self.motion.clear();
        for &h in &self.bodies {
            let rb = &self.live.bodies[h];
            let (v, w) = (rb.linvel(), rb.angvel());
            self.motion.push([v.x, v.y, v.z, w.x, w.y, w.z]);
        }
    }

    /// Forgets the kept velocities: accelerations read 0 until the next step.
    pub(crate) fn forget_motion(&mut self) {
        self.motion.clear();
    }

    fn frame_pose(&self, f: &Frame) -> (V3, Rotation) {
        let pose = self.site_pose(Units::Si, f.instance, f.point, f.rotation);
        let q = Rotation::from_xyzw(pose[4], pose[5], pose[6], pose[3]);
        ([pose[0], pose[1], pose[2]].map(f64::from), q)
    }

    /// The motion of the body-fixed point `p` (world m) of `instance`'s body.
    fn point_motion(&self, instance: usize, p: V3) -> Motion {
        if let Some(helper) = self.planar_helper(instance) {
            return Motion {
                p,
                v: v3(self.helper_motion(helper).1),
                w: [0.0; 3],
            };
        }
        let rb = &self.live.bodies[self.bodies[instance]];
        let w = v3(rb.angvel());
        let arm = sub(p, v3(rb.center_of_mass()));
        Motion {
            p,
            v: add(v3(rb.linvel()), cross(w, arm)),
            w,
        }
    }

    /// The acceleration of the body-fixed point `p` of `instance`'s body over the last step,
    /// and the body's angular acceleration (zeros without a kept motion).
    fn point_acceleration(&self, instance: usize, p: V3) -> (V3, V3) {
        let Some(start) = self.motion.get(instance) else {
            return ([0.0; 3], [0.0; 3]);
        };
        let rb = &self.live.bodies[self.bodies[instance]];
        let inv_dt = 1.0 / self.dt();
        let w = v3(rb.angvel());
        let a_c = scale(
            sub(
                v3(rb.linvel()),
                v3(Vector::new(start[0], start[1], start[2])),
            ),
            inv_dt,
        );
        let alpha = scale(
            sub(w, v3(Vector::new(start[3], start[4], start[5]))),
            inv_dt,
        );
        let r = sub(p, v3(rb.center_of_mass()));
        let a = add(add(a_c, cross(alpha, r)), cross(w, cross(w, r)));
        (a, alpha)
    }

    /// An instance's own mass (kg), centre of mass (world m) and inertia about it (world).
    fn own_inertia(&self, instance: usize) -> (f64, V3, [[f64; 3]; 3]) {
        let props = self.own_mass_properties(instance);
        let m = f64::from(props.mass());
        let axes = self.body_frame(instance).rotation * props.principal_inertia_local_frame;
        let principal = props.principal_inertia();
        let mut inertia = [[0.0; 3]; 3];
        for (axis, moment) in [
            (axes * Vector::X, principal.x),
            (axes * Vector::Y, principal.y),
            (axes * Vector::Z, principal.z),
        ] {
            let c = v3(axis);
            for i in 0..3 {
                for j in 0..3 {
                    inertia[i][j] += f64::from(moment) * c[i] * c[j];
                }
            }
        }
        (m, v3(self.own_center_of_mass(instance)), inertia)
    }

    fn read_sensor(
        &self,
        s: &SensorReading,
        magnetic: V3,
        wrenches: &mut Vec<[f64; 6]>,
        out: &mut [f64],
    ) {
        use SensorType::*;
        let set3 = |out: &mut [f64], v: V3| out.copy_from_slice(&v);
        match (&s.object, s.kind) {
            (Object::Dof(k), Jointpos) => out[0] = self.scalar_dof_si(*k).0,
            (Object::Dof(k), Jointvel) => out[0] = self.scalar_dof_si(*k).1,
            (Object::Actuator(k), _) => out[0] = self.actuator_force(*k),
            (Object::Direct(k), _) => {
                let d = &self.dofs[*k];
                out[0] = if d.gear != 0.0 {
                    self.dof_actuator_force(*k) / d.gear
                } else {
                    0.0
                };
            }
            (Object::Tendon(k), Tendonpos) => out[0] = self.tendon_state(*k).0,
            (Object::Tendon(k), _) => out[0] = self.tendon_state(*k).1,
            (Object::Subtree(members), kind) => set3(out, self.subtree_reading(members, kind)),
            (Object::Frame(f, below), _) => self.read_frame(s, f, below, magnetic, wrenches, out),
            _ => out.fill(0.0),
        }
    }

    /// A sensor on a frame: `f` (its instance's body, and the instances `below` it or
    /// welded to it).
    fn read_frame(
        &self,
        s: &SensorReading,
        f: &Frame,
        below: &[usize],
        magnetic: V3,
        wrenches: &mut Vec<[f64; 6]>,
        out: &mut [f64],
    ) {
        use SensorType::*;
        let set3 = |out: &mut [f64], v: V3| out.copy_from_slice(&v);
        let kind = s.kind;
        let (p, q) = self.frame_pose(f);
        let reference = s.reference.map(|r| self.frame_pose(&r));
        match kind {
            Framepos => set3(
                out,
                match reference {
                    Some((rp, rq)) => local(rq, sub(p, rp)),
                    None => p,
                },
            ),
            Framequat => {
                let q = match reference {
                    Some((_, rq)) => rq.inverse() * q,
                    None => q,
                };
                out.copy_from_slice(&[q.w, q.x, q.y, q.z].map(f64::from));
            }
            Framexaxis | Frameyaxis | Framezaxis => {
                let axis = match kind {
                    Framexaxis => Vector::X,
                    Frameyaxis => Vector::Y,
                    _ => Vector::Z,
                };
                let a = v3(q * axis);
                set3(out, reference.map_or(a, |(_, rq)| local(rq, a)));
            }
            Framelinvel | Frameangvel => {
                let m = self.point_motion(f.instance, p);
                let (v, w) = match s.reference {
                    Some(r) => {
                        let (rp, rq) = self.frame_pose(&r);
                        let rm = self.point_motion(r.instance, rp);
                        let v = sub(sub(m.v, rm.v), cross(rm.w, sub(m.p, rp)));
                        (local(rq, v), local(rq, sub(m.w, rm.w)))
                    }
                    None => (m.v, m.w),
                };
                set3(out, if kind == Framelinvel { v } else { w });
            }
            Framelinacc | Frameangacc => {
                let (a, alpha) = self.point_acceleration(f.instance, p);
                set3(out, if kind == Framelinacc { a } else { alpha });
            }
            Gyro => set3(out, local(q, self.point_motion(f.instance, p).w)),
            Velocimeter => set3(out, local(q, self.point_motion(f.instance, p).v)),
            Magnetometer => set3(out, local(q, magnetic)),
            Accelerometer => {
                let a = self.point_acceleration(f.instance, p).0;
                set3(out, local(q, sub(a, v3(self.gravity))));
            }
            Touch => out[0] = self.touch(below, s.volume.map(|v| (p, q, v))),
            Force | Torque => {
                if wrenches.is_empty() {
                    self.contact_wrenches([0.0; 3], wrenches);
                }
                let (force, torque) = self.interaction(below, p, wrenches);
                set3(out, local(q, if kind == Force { force } else { torque }));
            }
            Rangefinder => out[0] = self.range(f.instance, p, q),
            _ => out.fill(0.0),
        }
    }

    fn subtree_reading(&self, members: &[usize], kind: SensorType) -> V3 {
        let parts: Vec<(f64, V3, [[f64; 3]; 3], Motion)> = members
            .iter()
            .map(|&i| {
                let (m, c, inertia) = self.own_inertia(i);
                (m, c, inertia, self.point_motion(i, c))
            })
            .collect();
        let mass: f64 = parts.iter().map(|p| p.0).sum();
        if mass <= 0.0 {
            return [0.0; 3];
        }
        let com = scale(
            parts.iter().fold([0.0; 3], |s, p| add(s, scale(p.1, p.0))),
            1.0 / mass,
        );
        let vel = scale(
            parts
                .iter()
                .fold([0.0; 3], |s, p| add(s, scale(p.3.v, p.0))),
            1.0 / mass,
        );
        match kind {
            SensorType::Subtreecom => com,
            SensorType::Subtreelinvel => vel,
            _ => parts.iter().fold([0.0; 3], |s, (m, c, inertia, motion)| {
                let spin = mat_vec(inertia, motion.w);
                let orbit = scale(cross(sub(*c, com), sub(motion.v, vel)), *m);
                add(s, add(spin, orbit))
            }),
        }
    }

    /// The normal force of the last step's contacts on `group`, N: those inside the
    /// site's volume (at `p`, turned by `q`) when it has one.
    fn touch(&self, group: &[usize], zone: Option<(V3, Rotation, Volume)>) -> f64 {
        let mut sum = 0.0;
        self.for_each_contact(|a, b, at, normal, _| {
            let on = |i: Option<usize>| i.is_some_and(|i| group.contains(&i));
            let inside = zone.is_none_or(|(p, q, volume)| inside(volume, local(q, sub(at, p))));
            if (on(a) || on(b)) && inside {
                sum += normal.abs();
            }
        });
        sum
    }

    /// The force and the torque about `p` that the instances `below` receive from their
    /// parent: their rate of momentum, less gravity and the contacts (`wrenches`: each
    /// instance's contact wrench about the world origin), world.
    fn interaction(&self, below: &[usize], p: V3, wrenches: &[[f64; 6]]) -> (V3, V3) {
        let g = v3(self.gravity);
        let (mut force, mut torque) = ([0.0; 3], [0.0; 3]);
        for &i in below {
            let (m, c, inertia) = self.own_inertia(i);
            let (a, alpha) = self.point_acceleration(i, c);
            let w = self.point_motion(i, c).w;
            let f = scale(sub(a, g), m);
            force = add(force, f);
            let spin = add(mat_vec(&inertia, alpha), cross(w, mat_vec(&inertia, w)));
            torque = add(torque, add(cross(sub(c, p), f), spin));
            if let Some(e) = wrenches.get(i) {
                let ef = [e[3], e[4], e[5]];
                force = sub(force, ef);
                // The contact torque about the origin, moved to `p`.
                let about_p = sub([e[0], e[1], e[2]], cross(p, ef));
                torque = sub(torque, about_p);
            }
        }
        (force, torque)
    }

    /// The distance (m) along the +z axis of `q` from `p` to the nearest collider not on
    /// `instance`'s body, −1 when the ray hits nothing.
    fn range(&self, instance: usize, p: V3, q: Rotation) -> f64 {
        let s = &self.live;
        let filter = QueryFilter::default().exclude_rigid_body(self.bodies[instance]);
        let query = s.broad_phase.as_query_pipeline(
            s.narrow_phase.query_dispatcher(),
            &s.bodies,
            &s.colliders,
            filter,
        );
        let ray = Ray::new(vec(p), q * Vector::Z);
        // Hollow shapes: a ray from inside one meets its surface, as MuJoCo's rays do.
        match query.cast_ray(&ray, Real::MAX, false) {
            Some((_, toi)) => f64::from(toi),
            None => -1.0,
        }
    }
}

/// A site's volume: its shape and MuJoCo's sizes (m).
type Volume = (gymfleet_assembly::SiteShape, [f64; 3]);

/// Whether the point `x` (in the site's axes, from its centre) is inside `volume`
/// (MuJoCo's `mju_insideGeom`).
fn inside((shape, s): Volume, x: V3) -> bool {
    use gymfleet_assembly::SiteShape::*;
    let sq = |v: f64| v * v;
    match shape {
        Sphere => sq(x[0]) + sq(x[1]) + sq(x[2]) <= sq(s[0]),
        Capsule => {
            let z = x[2].clamp(-s[1], s[1]);
            sq(x[0]) + sq(x[1]) + sq(x[2] - z) <= sq(s[0])
        }
        Cylinder => sq(x[0]) + sq(x[1]) <= sq(s[0]) && x[2].abs() <= s[1],
        Ellipsoid => {
            (0..3).all(|k| s[k] > 0.0) && (0..3).map(|k| sq(x[k] / s[k])).sum::<f64>() <= 1.0
        }
        Box => (0..3).all(|k| x[k].abs() <= s[k]),
    }
}

fn mat_vec(m: &[[f64; 3]; 3], v: V3) -> V3 {
    [0, 1, 2].map(|i| m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2])
}
