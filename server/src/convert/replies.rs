//! Domain results into proto replies: infos, observations, step results, scenes, images,
//! randomization draws and the server's info.

use gymfleet_batch::Autoreset;
use gymfleet_env::{DofKind, DrawReport, EnvSpec, ObservationParts, Units};
use gymfleet_proto::v1 as pb;

use crate::domain::{
    BatchObservations, BatchStepped, JointLinks, Observed, Rendered, ServerStatus,
};

/// A format as the wire writes it.
pub(crate) fn format_to_proto(format: gymfleet_import::Format) -> pb::DocumentFormat {
    match format {
        gymfleet_import::Format::Json => pb::DocumentFormat::Json,
        gymfleet_import::Format::Urdf => pb::DocumentFormat::Urdf,
        gymfleet_import::Format::Mjcf => pb::DocumentFormat::Mjcf,
    }
}

/// Units as the wire writes them.
pub(super) fn units_to_proto(units: Units) -> i32 {
    let units = match units {
        Units::Document => pb::Units::Document,
        Units::Si => pb::Units::Si,
    };
    units as i32
}

/// An env's draws as the proto's.
pub(crate) fn randomization_draws(report: DrawReport) -> pb::RandomizationDraws {
    pb::RandomizationDraws {
        instances: report
            .instances
            .into_iter()
            .map(|(name, mass_scale, friction_scale)| pb::InstanceDraw {
                name,
                mass_scale,
                friction_scale,
            })
            .collect(),
        joints: report
            .joints
            .into_iter()
            .map(|(name, damping_scale, gain_scale)| pb::JointDraw {
                name,
                damping_scale,
                gain_scale,
            })
            .collect(),
    }
}

/// An env's scene on the wire.
/// Every instance's and site's state, flattened as `Bodies` lays it out.
pub(crate) fn bodies(b: gymfleet_env::Bodies) -> pb::Bodies {
    fn flat<const N: usize, T: Copy + Into<f64>>(rows: &[[T; N]]) -> Vec<f64> {
        rows.iter().flatten().map(|&v| v.into()).collect()
    }
    pb::Bodies {
        masses: b.masses,
        centers_of_mass: flat(&b.centers_of_mass),
        inertias: flat(&b.inertias),
        velocities: flat(&b.velocities),
        contact_wrenches: flat(&b.contact_wrenches),
        about: b.about.to_vec(),
        site_poses: flat(&b.site_poses),
        actuator_forces: b.actuator_forces,
        instances: b.instances,
        sites: b.sites,
        sensor_types: b.sensors.iter().map(|s| s.1.to_string()).collect(),
        sensor_dims: b.sensors.iter().map(|s| s.2 as u32).collect(),
        sensors: b.sensors.into_iter().map(|s| s.0).collect(),
        sensor_data: b.sensor_data,
    }
}

pub(crate) fn scene(scene: gymfleet_env::Scene) -> pb::Scene {
    let v = |p: [f32; 3]| pb::Vec3 {
        x: f64::from(p[0]),
        y: f64::from(p[1]),
        z: f64::from(p[2]),
    };
    let shape = |s: &gymfleet_env::SceneShape| {
        use pb::scene_shape::Kind;
        let kind = match *s {
            gymfleet_env::SceneShape::Cuboid { half_extents } => {
                Kind::BoxHalfExtents(v(half_extents))
            }
            gymfleet_env::SceneShape::Cylinder {
                radius,
                half_height,
            } => Kind::Cylinder(pb::SceneCylinder {
                radius: f64::from(radius),
                half_height: f64::from(half_height),
            }),
            gymfleet_env::SceneShape::Ball { radius } => Kind::SphereRadius(f64::from(radius)),
            gymfleet_env::SceneShape::Capsule {
                radius,
                half_segment,
            } => Kind::Capsule(pb::SceneCapsule {
                radius: f64::from(radius),
                half_segment: f64::from(half_segment),
            }),
            gymfleet_env::SceneShape::Mesh {
                ref vertices,
                ref triangles,
            } => Kind::Mesh(pb::SceneMesh {
                vertices: vertices.iter().flatten().copied().collect(),
                triangles: triangles.iter().flatten().copied().collect(),
            }),
        };
        pb::SceneShape { kind: Some(kind) }
    };
    pb::Scene {
        bodies: scene
            .parts
            .iter()
            .map(|part| {
                let [qw, qx, qy, qz] = part.rotation.map(f64::from);
                pb::SceneBody {
                    name: scene.instance_names[part.instance].clone(),
                    shape: Some(shape(&part.shape)),
                    pose: Some(pb::ScenePose {
                        position: Some(v(part.position)),
                        qw,
                        qx,
                        qy,
                        qz,
                    }),
                }
            })
            .collect(),
        joints: scene
            .joints
            .iter()
            .map(|j| pb::SceneJoint {
                anchor: Some(v(j.anchor)),
                axis: Some(v(j.axis)),
            })
            .collect(),
        end_effectors: scene.end_effectors.iter().map(|&p| v(p)).collect(),
        target: scene.target.map(v),
    }
}

/// A picture on the wire.
pub(crate) fn image(r: Rendered) -> pb::Image {
    pb::Image {
        png: r.png,
        width: r.width,
        height: r.height,
        description: r.description,
        grid_mm: r.grid_mm,
    }
}

/// A single env's observation in its proto form, split along the env's layout.
pub(crate) fn observation(observed: &Observed) -> pb::Observation {
    let parts = ObservationParts::split(&observed.layout, &observed.flat);
    pb::Observation {
        joint_positions: parts.joint_positions.to_vec(),
        joint_velocities: parts.joint_velocities.to_vec(),
        end_effector_poses: parts.end_effector_poses.to_vec(),
        task_observation: parts.task.to_vec(),
        base_pose: parts.base_pose.to_vec(),
        base_velocity: parts.base_velocity.to_vec(),
        free_body_poses: parts.free_body_poses.to_vec(),
        free_body_velocities: parts.free_body_velocities.to_vec(),
    }
}

pub(super) fn observation_layout(spec: &EnvSpec) -> Vec<pb::ObservationSegment> {
    spec.observation_layout
        .iter()
        .map(|s| pb::ObservationSegment {
            name: s.name.to_string(),
            size: to_u32(s.size),
        })
        .collect()
}

pub(super) fn to_u32(n: usize) -> u32 {
    u32::try_from(n).unwrap_or(u32::MAX)
}

/// The proto description of each non-fixed joint, from the spec's DOFs.
pub(crate) fn joints(spec: &EnvSpec, links: &JointLinks) -> Vec<pb::JointInfo> {
    let mut joints: Vec<pb::JointInfo> = Vec::with_capacity(spec.num_joints);
    let mut last = None;
    for dof in &spec.dofs {
        if last != Some(dof.joint) {
            last = Some(dof.joint);
            let (parent, child) = links.0.get(joints.len()).cloned().unwrap_or_default();
            joints.push(pb::JointInfo {
                name: dof.joint_name.clone(),
                r#type: dof.joint_type.as_str().to_string(),
                kind: joint_kind(dof.joint_type) as i32,
                dof: 0,
                limits: Vec::new(),
                parent,
                child,
                max_effort: dof.max_effort,
                actuated: dof.actuated,
                gear: dof.gear,
                reference: dof.reference,
                action_bounds: Vec::new(),
            });
        }
        if let Some(joint) = joints.last_mut() {
            joint.dof += 1;
            joint.action_bounds.push(dof.action_bound);
            joint.limits.push(pb::DofLimit {
                unit: match dof.kind {
                    DofKind::Angular => "deg",
                    DofKind::Linear => "mm",
                }
                .to_string(),
                dof_unit: match dof.kind {
                    DofKind::Angular => pb::DofUnit::Deg,
                    DofKind::Linear => pb::DofUnit::Mm,
                } as i32,
                min: dof.limits.map(|l| l[0]),
                max: dof.limits.map(|l| l[1]),
            });
        }
    }
    joints
}

/// The proto description of each actuator.
pub(crate) fn actuators(spec: &EnvSpec) -> Vec<pb::ActuatorInfo> {
    spec.actuators
        .iter()
        .map(|a| pb::ActuatorInfo {
            name: a.name.clone(),
            r#type: a.kind.clone(),
            target: a.target.clone(),
            ctrl_min: a.ctrl_range.map(|r| r[0]),
            ctrl_max: a.ctrl_range.map(|r| r[1]),
        })
        .collect()
}

/// The proto `EnvInfo` of a created env.
pub(crate) fn env_info(env_id: String, spec: &EnvSpec, links: &JointLinks) -> pb::EnvInfo {
    pb::EnvInfo {
        env_id,
        num_joints: to_u32(spec.num_joints),
        action_dim: to_u32(spec.action_dim),
        observation_dim: to_u32(spec.observation_dim),
        end_effector_ids: spec.end_effector_ids.clone(),
        dt: spec.dt,
        substeps: spec.substeps,
        max_steps: spec.max_steps,
        joints: joints(spec, links),
        observation_layout: observation_layout(spec),
        units: units_to_proto(spec.units),
        term_names: spec.term_names.clone(),
        free_bodies: spec.free_bodies.clone(),
        mocap_bodies: spec.mocap_bodies.clone(),
        moving_mass: spec.moving_mass,
        actuators: actuators(spec),
        keyframes: spec.keyframes.clone(),
        heightfields: heightfields(spec),
    }
}

/// The heightfields an env spec names, as proto.
fn heightfields(spec: &EnvSpec) -> Vec<pb::HeightfieldInfo> {
    spec.heightfields
        .iter()
        .map(|(name, rows, columns)| pb::HeightfieldInfo {
            name: name.clone(),
            rows: to_u32(*rows),
            columns: to_u32(*columns),
        })
        .collect()
}

/// The proto `BatchInfo` of a created batch.
pub(crate) fn batch_info(
    batch_id: String,
    n_envs: usize,
    autoreset: Autoreset,
    spec: &EnvSpec,
    links: &JointLinks,
) -> pb::BatchInfo {
    let env = env_info(String::new(), spec, links);
    // Older clients read the flat fields, which repeat `env`.
    #[allow(deprecated)]
    let info = pb::BatchInfo {
        batch_id,
        n_envs: to_u32(n_envs),
        autoreset: match autoreset {
            Autoreset::Disabled => pb::Autoreset::Disabled,
            Autoreset::SameStep => pb::Autoreset::SameStep,
            Autoreset::NextStep => pb::Autoreset::NextStep,
        } as i32,
        action_dim: env.action_dim,
        observation_dim: env.observation_dim,
        num_joints: env.num_joints,
        end_effector_ids: env.end_effector_ids.clone(),
        dt: env.dt,
        substeps: env.substeps,
        max_steps: env.max_steps,
        joints: env.joints.clone(),
        observation_layout: env.observation_layout.clone(),
        units: env.units,
        term_names: env.term_names.clone(),
        free_bodies: env.free_bodies.clone(),
        mocap_bodies: env.mocap_bodies.clone(),
        moving_mass: env.moving_mass,
        actuators: env.actuators.clone(),
        keyframes: env.keyframes.clone(),
        heightfields: env.heightfields.clone(),
        env: Some(env),
    };
    info
}

/// A termination reason as the proto's enum.
pub(crate) fn termination(why: gymfleet_env::Termination) -> pb::TerminationReason {
    use gymfleet_env::Termination;
    match why {
        Termination::PhysicsDiverged => pb::TerminationReason::PhysicsDiverged,
        Termination::GoalReached => pb::TerminationReason::GoalReached,
        Termination::Fell => pb::TerminationReason::Fell,
        Termination::Unhealthy => pb::TerminationReason::Unhealthy,
    }
}

/// A joint type as the proto's enum (a fixed joint is not listed).
fn joint_kind(kind: gymfleet_assembly::JointType) -> pb::JointType {
    use gymfleet_assembly::JointType;
    match kind {
        JointType::Revolute => pb::JointType::Revolute,
        JointType::Prismatic => pb::JointType::Prismatic,
        JointType::Cylindrical => pb::JointType::Cylindrical,
        JointType::Ball => pb::JointType::Ball,
        JointType::Fixed => pb::JointType::Unspecified,
    }
}

/// The proto result of a batch step.
pub(crate) fn batch_step_result(stepped: BatchStepped) -> pb::BatchStepResult {
    let BatchStepped {
        batch_id,
        step_index,
        out,
        env_indices,
    } = stepped;
    pb::BatchStepResult {
        batch_id,
        step_index,
        observations: out.observations,
        rewards: out.rewards,
        terminated: out.terminated,
        truncated: out.truncated,
        final_env_indices: out.final_env_indices,
        final_observations: out.final_observations,
        terminations: out
            .termination_reasons
            .iter()
            .map(|(&env, &why)| (env, termination(why) as i32))
            .collect(),
        termination_reasons: out
            .termination_reasons
            .into_iter()
            .map(|(env, why)| (env, why.as_str().to_string()))
            .collect(),
        terms: out.terms,
        env_indices,
    }
}

/// The proto observations of a batch.
pub(crate) fn batch_observation(batch: BatchObservations) -> pb::BatchObservation {
    pb::BatchObservation {
        batch_id: batch.batch_id,
        n_envs: to_u32(batch.n_envs),
        observation_dim: to_u32(batch.observation_dim),
        observations: batch.observations,
    }
}

/// The proto `ServerInfo`.
pub(crate) fn server_info(status: &ServerStatus<'_>) -> pb::ServerInfo {
    let c = status.config;
    let u64_of = |n: usize| u64::try_from(n).unwrap_or(u64::MAX);
    pb::ServerInfo {
        version: env!("CARGO_PKG_VERSION").to_string(),
        threads: to_u32(status.threads),
        envs: u64_of(status.envs),
        batches: u64_of(status.batches),
        batch_envs: u64_of(status.batch_envs),
        limits: Some(pb::ServerLimits {
            max_envs: u64_of(c.max_envs),
            max_batch_size: u64_of(c.max_batch_size),
            max_document_bytes: u64_of(c.max_document_bytes),
            max_message_bytes: u64_of(c.max_message_bytes),
            idle_ttl_seconds: c.idle_ttl.as_secs(),
            max_instances: u64_of(c.max_instances),
            max_joints: u64_of(c.max_joints),
            max_dofs: u64_of(c.max_dofs),
            max_end_effectors: u64_of(c.max_end_effectors),
            tenant_max_envs: u64_of(c.tenant_max_envs),
            max_step_work: u64_of(c.max_step_work),
            max_contact_work: u64_of(c.max_contact_work),
        }),
        tenant: status.tenant.name().to_string(),
        auth_required: c.auth_tokens.is_some(),
        instance_id: status.instance_id.to_string(),
    }
}
