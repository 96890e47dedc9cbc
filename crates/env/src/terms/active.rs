//! A terms task resolved against one env ([`ActiveTerms`]): its terms evaluated after
//! every step, and the reset's draws ([`Dist`], [`ActiveSet`]).

use std::cell::{OnceCell, RefCell};

use gymfleet_physics::{RobotWorld, Units, INERTIA_LEN, VELOCITY_LEN, WRENCH_LEN};
use rand::rngs::Xoshiro256PlusPlus;
use rand::RngExt;

use super::tolerance::ActiveTolerance;
use crate::episode::Termination;

/// A [`SetJoints`] resolved: DOF indices and bounds.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ActiveSet {
    pub(crate) dofs: Vec<usize>,
    /// Normal draws: `low` the means, `high` the standard deviations.
    pub(super) normal: bool,
    /// Whether the drawn joints start at rest.
    pub(crate) at_rest: bool,
    pub(super) low: Vec<f64>,
    pub(super) high: Vec<f64>,
    pub(super) min_norm: f64,
    pub(super) max_norm: f64,
}

/// Draws before a set's last draw is scaled into its norm range.
const MAX_SET_DRAWS: usize = 1000;

impl ActiveSet {
    /// Draws the joints' positions (the env's units) into `out`.
    pub(crate) fn draw(&self, rng: &mut Xoshiro256PlusPlus, out: &mut [f64]) {
        if self.normal {
            for (k, o) in out.iter_mut().enumerate() {
                *o = self.low[k] + Dist::Normal(self.high[k]).draw(rng);
            }
            return;
        }
        for _ in 0..MAX_SET_DRAWS {
            for (k, o) in out.iter_mut().enumerate() {
                *o = if self.low[k] < self.high[k] {
                    rng.random_range(self.low[k]..=self.high[k])
                } else {
                    self.low[k]
                };
            }
            let norm = out.iter().map(|v| v * v).sum::<f64>().sqrt();
            if norm >= self.min_norm && norm <= self.max_norm {
                return;
            }
        }
        let norm = out.iter().map(|v| v * v).sum::<f64>().sqrt();
        let target = norm.clamp(self.min_norm, self.max_norm);
        if norm > 0.0 {
            out.iter_mut().for_each(|v| *v *= target / norm);
        }
    }
}

/// A distribution as drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Dist {
    Uniform(f64),
    Normal(f64),
}

impl Dist {
    /// One draw from the env's stream.
    pub(crate) fn draw(self, rng: &mut Xoshiro256PlusPlus) -> f64 {
        match self {
            Dist::Uniform(s) => rng.random_range(-s..=s),
            Dist::Normal(s) => {
                // Box–Muller: u1 in (0, 1] keeps the logarithm finite.
                let u1: f64 = 1.0 - rng.random::<f64>();
                let u2: f64 = rng.random::<f64>();
                s * (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
            }
        }
    }
}

/// A quantity resolved against the env.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Q {
    Position(usize),
    Velocity(usize),
    LimitForce(usize),
    TendonLength(usize),
    TendonVelocity(usize),
    ActuatorForce(usize),
    /// An actuator's force (MuJoCo's `actuator_force`).
    Actuator(usize),
    /// An actuator's activation.
    Activation(usize),
    /// A float of the sensors' readings (MuJoCo's `sensordata[k]`).
    Sensor(usize),
    /// A component of a group's `cinert` ([`ActiveTerms::groups`]).
    BodyInertia {
        group: usize,
        component: usize,
    },
    /// A component of a group's `cvel`.
    BodyVelocity {
        group: usize,
        component: usize,
    },
    /// A component of a group's contact wrench ([`ActiveTerms::groups`]).
    ContactWrench {
        group: usize,
        component: usize,
    },
    Point {
        body: usize,
        point: Option<[f64; 3]>,
        axis: usize,
    },
    CenterOfMass(usize),
    /// The world `axis` component of a frame's own axis `local`: the instance's, turned
    /// by a site's rotation (MuJoCo's `xmat[axis, local]`).
    FrameAxis {
        body: usize,
        rotation: [f64; 3],
        local: usize,
        axis: usize,
    },
    /// One value of the step's action.
    Action(usize),
    /// A point's offset from a site's frame, along the frame's axis `axis`.
    Relative {
        body: usize,
        point: Option<[f64; 3]>,
        frame: (usize, [f64; 3], [f64; 3]),
        axis: usize,
    },
    /// A world coordinate of a group's centre of mass (SI), from its `cinert`.
    BodyCenter {
        group: usize,
        axis: usize,
    },
}

#[derive(Debug, Clone, PartialEq)]
pub(super) enum Kind {
    Velocity(Q),
    Value(Q),
    CtrlCost,
    Healthy,
    Distance([(usize, Option<[f64; 3]>); 2]),
    Square(Q, f64),
    ContactCost {
        groups: Vec<usize>,
        lo: f64,
        hi: f64,
        sum_max: f64,
    },
    Tolerance(ActiveTolerance),
    /// Π, Σ or the norm of (scale · value + offset) of earlier terms.
    Combine {
        op: Op,
        factors: Vec<(usize, f64, f64)>,
    },
}

/// How a `Combine` term combines its factors.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Op {
    Product,
    Sum,
    Norm,
}

#[derive(Debug, Clone, PartialEq)]
pub(super) struct ActiveHealthy {
    pub(super) ranges: Vec<(Q, f64, f64)>,
    pub(super) state: Option<(f64, f64, usize)>,
    pub(super) terminate: bool,
}

/// A terms task resolved against one env.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ActiveTerms {
    pub(super) terms: Vec<(f64, Kind)>,
    /// The observed terms (all `value` terms), in term order.
    pub(super) observed: Vec<usize>,
    pub(super) healthy: Option<ActiveHealthy>,
    /// Each velocity term's coordinate at the end of the last step (or reset).
    pub(super) previous: Vec<f64>,
    pub(super) units: Units,
    pub(super) dt: f64,
    /// Groups of instances whose contact wrenches some term reads.
    pub(super) groups: Vec<Vec<usize>>,
    /// Each instance's contact wrench after the last step (scratch, read when `groups`
    /// is not empty).
    pub(super) wrenches: Vec<[f64; WRENCH_LEN]>,
    pub(crate) position_noise: Option<Dist>,
    /// Whether the noise moves the floating base too ([`super::ResetNoise::base`]).
    pub(crate) base_noise: bool,
    /// Substeps run with a zero action after the draws ([`super::ResetNoise::settle_substeps`]).
    pub(crate) settle_substeps: u32,
    /// Whether a floating base starts at a random orientation ([`super::ResetNoise::rotational`]).
    pub(crate) turn_base: bool,
    /// Whether a start is drawn again while colliders overlap.
    pub(crate) reject_contacts: bool,
    /// Where mocap bodies start.
    pub(crate) mocap_draws: Vec<super::ActiveMocapDraw>,
    pub(crate) velocity_noise: Option<Dist>,
    pub(crate) sets: Vec<ActiveSet>,
    /// Joints placed by one of several options ([`super::ResetNoise::choice`]).
    pub(crate) choice: Option<super::choice::ActiveChoice>,
    /// DOF pairs `(a, b)`: `a` starts where `b` does ([`super::ResetNoise::equal`]).
    pub(crate) equal: Vec<(usize, usize)>,
    /// This step's values in f64 (scratch), which later terms read.
    pub(super) step_values: Vec<f64>,
}

/// What terms read at one moment: the world, the observed joint state, and the robot's
/// centre of mass (SI; what body-level terms are taken about), computed once, when first
/// needed; likewise each group's inertia and velocity, which a body's ten and six terms
/// share.
struct Now<'a> {
    world: &'a RobotWorld,
    positions: &'a [f32],
    velocities: &'a [f32],
    /// The step's action (empty at a reset: every value reads 0).
    action: &'a [f32],
    com: OnceCell<[f64; 3]>,
    inertia: RefCell<Vec<(usize, [f64; INERTIA_LEN])>>,
    velocity: RefCell<Vec<(usize, [f64; VELOCITY_LEN])>>,
    sensors: OnceCell<Vec<f64>>,
}

impl<'a> Now<'a> {
    fn new(
        world: &'a RobotWorld,
        positions: &'a [f32],
        velocities: &'a [f32],
        action: &'a [f32],
    ) -> Self {
        Now {
            world,
            positions,
            velocities,
            action,
            com: OnceCell::new(),
            inertia: RefCell::new(Vec::new()),
            velocity: RefCell::new(Vec::new()),
            sensors: OnceCell::new(),
        }
    }

    /// Every sensor's reading, computed once.
    fn sensor(&self, k: usize) -> f64 {
        let data = self.sensors.get_or_init(|| {
            let mut data = vec![0.0; self.world.sensor_dim()];
            self.world.sensor_data(&mut data);
            data
        });
        data.get(k).copied().unwrap_or(0.0)
    }

    /// `group`'s `cinert` about the centre of mass, computed once per group.
    fn inertia(&self, group: usize, members: &[usize]) -> [f64; INERTIA_LEN] {
        once_per_group(&self.inertia, group, || {
            self.world.group_inertia(members, self.com())
        })
    }

    /// `group`'s `cvel` at the centre of mass, computed once per group.
    fn velocity(&self, group: usize, members: &[usize]) -> [f64; VELOCITY_LEN] {
        once_per_group(&self.velocity, group, || {
            self.world.group_velocity(members, self.com())
        })
    }

    /// The robot's centre of mass, m (MuJoCo's root subtree centre of mass).
    fn com(&self) -> [f64; 3] {
        *self
            .com
            .get_or_init(|| self.world.robot_center_of_mass(Units::Si))
    }
}

/// The rotation matrix of the unit quaternion `[w, x, y, z]`, rows the world axes:
/// `m[i][j]` is the world `i` component of the frame's axis `j` (MuJoCo's `xmat`).
pub(crate) fn rotation_matrix([w, x, y, z]: [f64; 4]) -> [[f64; 3]; 3] {
    [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - w * z),
            2.0 * (x * z + w * y),
        ],
        [
            2.0 * (x * y + w * z),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - w * x),
        ],
        [
            2.0 * (x * z - w * y),
            2.0 * (y * z + w * x),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ]
}

/// `group`'s value in `cache`, computed by `compute` the first time it is asked for.
fn once_per_group<const N: usize>(
    cache: &RefCell<Vec<(usize, [f64; N])>>,
    group: usize,
    compute: impl FnOnce() -> [f64; N],
) -> [f64; N] {
    if let Some((_, value)) = cache.borrow().iter().find(|(g, _)| *g == group) {
        return *value;
    }
    let value = compute();
    cache.borrow_mut().push((group, value));
    value
}

impl ActiveTerms {
    fn read(&self, q: Q, now: &Now) -> f64 {
        let (world, positions, velocities) = (now.world, now.positions, now.velocities);
        match q {
            Q::Position(k) => f64::from(positions[k]),
            Q::Velocity(k) => f64::from(velocities[k]),
            Q::LimitForce(k) => world.limit_force(k),
            Q::TendonLength(k) => world.tendon_state(k).0,
            Q::TendonVelocity(k) => world.tendon_state(k).1,
            Q::ActuatorForce(k) => world.dof_actuator_force(k),
            Q::Actuator(k) => world.actuator_force(k),
            Q::Activation(k) => world.actuator_activation(k),
            Q::Sensor(k) => now.sensor(k),
            Q::BodyInertia { group, component } => {
                now.inertia(group, &self.groups[group])[component]
            }
            Q::BodyVelocity { group, component } => {
                now.velocity(group, &self.groups[group])[component]
            }
            Q::ContactWrench { group, component } => self.group_wrench(group)[component],
            Q::Point { body, point, axis } => match point {
                Some(p) => world.point_position(self.units, body, p)[axis],
                None => world.center_of_mass(self.units, body)[axis],
            },
            Q::CenterOfMass(axis) => world.robot_center_of_mass(self.units)[axis],
            Q::FrameAxis {
                body,
                rotation,
                local,
                axis,
            } => {
                let p = world.site_pose(self.units, body, [0.0; 3], rotation);
                let [w, x, y, z] = [p[3], p[4], p[5], p[6]].map(f64::from);
                rotation_matrix([w, x, y, z])[axis][local]
            }
            Q::Action(k) => now.action.get(k).map_or(0.0, |&a| f64::from(a)),
            Q::Relative {
                body,
                point,
                frame: (fbody, fpoint, rotation),
                axis,
            } => {
                let p = self.point(world, (body, point));
                let f = world.site_pose(self.units, fbody, fpoint, rotation);
                let m = rotation_matrix([f[3], f[4], f[5], f[6]].map(f64::from));
                (0..3).map(|i| m[i][axis] * (p[i] - f64::from(f[i]))).sum()
            }
            Q::BodyCenter { group, axis } => {
                let c = now.inertia(group, &self.groups[group]);
                let mass = c[INERTIA_LEN - 1];
                let offset = if mass > 0.0 { c[6 + axis] / mass } else { 0.0 };
                now.com()[axis] + offset
            }
        }
    }

    fn point(&self, world: &RobotWorld, (body, point): (usize, Option<[f64; 3]>)) -> [f64; 3] {
        match point {
            Some(p) => world.point_position(self.units, body, p),
            None => world.center_of_mass(self.units, body),
        }
    }

    /// The summed contact wrench of group `g`.
    fn group_wrench(&self, g: usize) -> [f64; WRENCH_LEN] {
        let mut sum = [0.0; WRENCH_LEN];
        for &i in &self.groups[g] {
            // None before the first step of an episode: no contact yet.
            if let Some(w) = self.wrenches.get(i) {
                for (s, w) in sum.iter_mut().zip(w) {
                    *s += w;
                }
            }
        }
        sum
    }

    /// Floats the observed terms add to the observation.
    pub(crate) fn observation_dim(&self) -> usize {
        self.observed.len()
    }

    /// The observed terms' values from the state now (contact wrenches: the last step's).
    pub(crate) fn observe(
        &self,
        world: &RobotWorld,
        positions: &[f32],
        velocities: &[f32],
        out: &mut [f32],
    ) {
        let now = Now::new(world, positions, velocities, &[]);
        for (o, &k) in out.iter_mut().zip(&self.observed) {
            if let Kind::Value(q) = self.terms[k].1 {
                *o = self.read(q, &now) as f32;
            }
        }
    }

    /// A new episode (or a state put back): the velocity terms' coordinates now.
    pub(crate) fn start(&mut self, world: &RobotWorld, positions: &[f32], velocities: &[f32]) {
        self.wrenches.clear();
        let now = Now::new(world, positions, velocities, &[]);
        for k in 0..self.terms.len() {
            if let Kind::Velocity(q) = self.terms[k].1 {
                self.previous[k] = self.read(q, &now);
            }
        }
    }

    fn is_healthy(&self, now: &Now) -> bool {
        let Some(h) = &self.healthy else { return true };
        let ranges = h.ranges.iter().all(|&(q, lo, hi)| {
            let v = self.read(q, now);
            lo < v && v < hi
        });
        let state = h.state.is_none_or(|(lo, hi, skip)| {
            now.positions[skip..]
                .iter()
                .chain(now.velocities)
                .all(|&v| lo < f64::from(v) && f64::from(v) < hi)
        });
        ranges && state
    }

    /// After a step: writes every term's value into `values`, and returns the reward
    /// (Σ weight · value) and the `unhealthy` termination if the task calls for it.
    pub(crate) fn evaluate(
        &mut self,
        world: &RobotWorld,
        positions: &[f32],
        velocities: &[f32],
        action: &[f32],
        values: &mut [f32],
    ) -> (f64, Option<Termination>) {
        let now = Now::new(world, positions, velocities, action);
        if !self.groups.is_empty() {
            // MuJoCo's cfrc_ext is about the root's subtree centre of mass.
            world.contact_wrenches(now.com(), &mut self.wrenches);
        }
        let healthy = self.is_healthy(&now);
        let mut reward = 0.0;
        for (k, slot) in values.iter_mut().enumerate().take(self.terms.len()) {
            let (weight, kind) = &self.terms[k];
            let value = match kind {
                Kind::Velocity(q) => {
                    let value = self.read(*q, &now);
                    let rate = (value - self.previous[k]) / self.dt;
                    self.previous[k] = value;
                    rate
                }
                Kind::Value(q) => self.read(*q, &now),
                Kind::CtrlCost => crate::action::sum_of_squares(action),
                Kind::Healthy => f64::from(u8::from(healthy)),
                Kind::Distance([a, b]) => {
                    let (a, b) = (self.point(world, *a), self.point(world, *b));
                    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
                }
                Kind::Square(q, center) => (self.read(*q, &now) - center).powi(2),
                Kind::ContactCost {
                    groups,
                    lo,
                    hi,
                    sum_max,
                } => groups
                    .iter()
                    .flat_map(|&g| self.group_wrench(g))
                    .map(|w| w.clamp(*lo, *hi).powi(2))
                    .sum::<f64>()
                    .min(*sum_max),
                Kind::Tolerance(t) => t.of_value(self.step_values[t.of]),
                Kind::Combine { op, factors } => {
                    let each = factors
                        .iter()
                        .map(|&(j, scale, offset)| scale * self.step_values[j] + offset);
                    match op {
                        Op::Product => each.product(),
                        Op::Sum => each.sum(),
                        Op::Norm => each.map(|v| v * v).sum::<f64>().sqrt(),
                    }
                }
            };
            self.step_values[k] = value;
            *slot = value as f32;
            reward += weight * value;
        }
        let terminate = self.healthy.as_ref().is_some_and(|h| h.terminate);
        (
            reward,
            (terminate && !healthy).then_some(Termination::Unhealthy),
        )
    }
}
