//! The world's sensors resolved from `Assembly::sensors` (evaluated in `sensors.rs`).

use gymfleet_assembly::{
    Assembly, Sensor, SensorFrame as AssemblyFrame, SensorObject as Target, SensorType,
};

/// The world's sensors, resolved once from the assembly (shared by a batch's copies).
#[derive(Debug, Default)]
pub(crate) struct SensorPlan {
    pub(crate) sensors: Vec<SensorReading>,
    /// Floats in all (MuJoCo's `nsensordata`).
    pub(crate) dim: usize,
    /// Whether a sensor needs the last step's accelerations.
    pub(crate) needs_motion: bool,
    pub(crate) magnetic: [f64; 3],
}

/// One sensor, resolved.
#[derive(Debug)]
pub(crate) struct SensorReading {
    pub(crate) kind: SensorType,
    pub(crate) object: SensorObject,
    /// A frame sensor's reference frame.
    pub(crate) reference: Option<SensorFrame>,
    pub(crate) cutoff: f64,
    /// A touch sensor's site's volume (shape, MuJoCo's sizes in m), if it has one.
    pub(crate) volume: Option<(gymfleet_assembly::SiteShape, [f64; 3])>,
}

/// What a sensor reads, resolved against the world.
#[derive(Debug)]
pub(crate) enum SensorObject {
    Dof(usize),
    Actuator(usize),
    /// A directly actuated DOF (its force is its effort over its gear).
    Direct(usize),
    Tendon(usize),
    /// A frame, and the instances below it (its subtree: force, torque) or welded to it
    /// (touch).
    Frame(SensorFrame, Vec<usize>),
    Subtree(Vec<usize>),
}

/// A frame on an instance: a point (mm in the instance's frame) and axes (radians, X then
/// Y then Z).
#[derive(Debug, Clone, Copy)]
pub(crate) struct SensorFrame {
    pub(crate) instance: usize,
    pub(crate) point: [f64; 3],
    pub(crate) rotation: [f64; 3],
}

impl SensorPlan {
    /// The assembly's sensors, resolved against the world's DOFs and bodies.
    pub(crate) fn new(assembly: &Assembly, dof_joints: &[usize], owners: &[usize]) -> Self {
        let dof_of = |joint: usize| dof_joints.iter().position(|&j| j == joint).unwrap_or(0);
        let frame = |f: AssemblyFrame| match f {
            AssemblyFrame::Site(k) => {
                let s = &assembly.sites[k];
                SensorFrame {
                    instance: s.instance,
                    point: s.point,
                    rotation: s.rotation,
                }
            }
            AssemblyFrame::Instance(i) => SensorFrame {
                instance: i,
                point: [0.0; 3],
                rotation: [0.0; 3],
            },
        };
        let sensors: Vec<SensorReading> = assembly
            .sensors
            .iter()
            .map(|s: &Sensor| SensorReading {
                kind: s.kind,
                object: match s.object {
                    Target::Joint(j) => SensorObject::Dof(dof_of(j)),
                    Target::Actuator(a) => SensorObject::Actuator(a),
                    Target::DirectActuator(j) => SensorObject::Direct(dof_of(j)),
                    Target::Tendon(t) => SensorObject::Tendon(t),
                    Target::Subtree(i) => SensorObject::Subtree(subtree(assembly, i)),
                    Target::Frame(f) => {
                        let f = frame(f);
                        let below = match s.kind {
                            SensorType::Force | SensorType::Torque => subtree(assembly, f.instance),
                            SensorType::Touch => (0..owners.len())
                                .filter(|&i| owners[i] == owners[f.instance])
                                .collect(),
                            _ => Vec::new(),
                        };
                        SensorObject::Frame(f, below)
                    }
                },
                reference: s.reference.map(frame),
                cutoff: s.cutoff,
                volume: match s.object {
                    Target::Frame(AssemblyFrame::Site(k)) if s.kind == SensorType::Touch => {
                        assembly.sites[k].volume
                    }
                    _ => None,
                },
            })
            .collect();
        SensorPlan {
            dim: assembly.sensor_dim(),
            needs_motion: sensors.iter().any(|s| s.kind.needs_acceleration()),
            sensors,
            magnetic: assembly.magnetic,
        }
    }
}

/// Instance `root` and every instance jointed below it (loop-closing joints left out).
fn subtree(assembly: &Assembly, root: usize) -> Vec<usize> {
    let mut out = vec![root];
    let mut k = 0;
    while k < out.len() {
        let parent = out[k];
        for j in assembly.joints.iter().filter(|j| !j.closes_loop) {
            if j.parent == parent && !out.contains(&j.child) {
                out.push(j.child);
            }
        }
        k += 1;
    }
    out
}
