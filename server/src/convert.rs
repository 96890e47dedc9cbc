//! The edge between the wire and the domain: `TryFrom` proto requests into domain
//! requests (validating what the domain cannot see, such as unset enums), and domain
//! results into proto replies. Proto types go no further than this module and
//! `service.rs`. This file holds the step, render and draw requests; `create.rs` the
//! create and fork requests (the env's options); `replies.rs` the replies.

use gymfleet_env::ActionType;
use gymfleet_proto::v1 as pb;
use gymfleet_render::{Camera, CameraPreset};

use crate::domain::{Action, BatchStep, DrawsOf, EnvStep, RenderOf};
use crate::error::{Result, ServerError};

mod create;
mod replies;

pub(crate) use create::document_format;
pub(crate) use replies::{
    batch_info, batch_observation, batch_step_result, bodies, env_info, format_to_proto, image,
    observation, randomization_draws, scene, server_info, termination,
};

/// A `SetMocapPoseRequest`'s pose: exactly 7 values (the env checks what they hold).
pub(crate) fn mocap_pose(values: &[f32]) -> Result<[f32; 7]> {
    <[f32; 7]>::try_from(values).map_err(|_| ServerError::InvalidArgument {
        field: "pose",
        reason: format!(
            "expected 7 values (x, y, z, qw, qx, qy, qz), got {}",
            values.len()
        ),
    })
}

fn action_type(raw: i32) -> Result<ActionType> {
    let expected = "expected ACTION_TYPE_TORQUE, ACTION_TYPE_POSITION or ACTION_TYPE_VELOCITY";
    match pb::ActionType::try_from(raw) {
        Ok(pb::ActionType::Torque) => Ok(ActionType::Torque),
        Ok(pb::ActionType::Position) => Ok(ActionType::Position),
        Ok(pb::ActionType::Velocity) => Ok(ActionType::Velocity),
        Ok(pb::ActionType::Unspecified) => Err(ServerError::InvalidArgument {
            field: "action_type",
            reason: format!("{expected}, got ACTION_TYPE_UNSPECIFIED (the field was not set)"),
        }),
        Err(_) => Err(ServerError::InvalidArgument {
            field: "action_type",
            reason: format!("{expected}, got unknown value {raw}"),
        }),
    }
}

impl TryFrom<pb::RandomizationRequest> for DrawsOf {
    type Error = ServerError;

    fn try_from(r: pb::RandomizationRequest) -> Result<Self> {
        DrawsOf::new(r.env_id, r.batch_id, r.env_index)
    }
}

impl DrawsOf {
    /// An env (`env_id`) or env `env_index` of a batch (`batch_id`): exactly one of the ids.
    fn new(env_id: String, batch_id: String, env_index: u32) -> Result<Self> {
        match (env_id.is_empty(), batch_id.is_empty()) {
            (false, true) => Ok(DrawsOf::Env(env_id)),
            (true, false) => Ok(DrawsOf::BatchEnv(batch_id, env_index as usize)),
            _ => Err(ServerError::InvalidArgument {
                field: "env_id",
                reason: "expected exactly one of env_id and batch_id".to_string(),
            }),
        }
    }
}

impl TryFrom<pb::RenderRequest> for RenderOf {
    type Error = ServerError;

    fn try_from(r: pb::RenderRequest) -> Result<Self> {
        let of = DrawsOf::new(r.env_id, r.batch_id, r.env_index)?;
        let camera = r.camera.unwrap_or_default();
        let preset = match pb::CameraPreset::try_from(camera.preset) {
            Ok(pb::CameraPreset::Unspecified | pb::CameraPreset::Iso) => CameraPreset::Iso,
            Ok(pb::CameraPreset::Front) => CameraPreset::Front,
            Ok(pb::CameraPreset::Side) => CameraPreset::Side,
            Ok(pb::CameraPreset::Top) => CameraPreset::Top,
            Err(_) => {
                return Err(ServerError::InvalidArgument {
                    field: "camera.preset",
                    reason: format!("unknown camera preset {}", camera.preset),
                })
            }
        };
        let point = |v: Option<pb::Vec3>| v.map(|v| [v.x as f32, v.y as f32, v.z as f32]);
        Ok(RenderOf {
            of,
            camera: Camera {
                preset,
                eye: point(camera.eye),
                target: point(camera.target),
                fov_deg: camera.fov_deg,
                orthographic: camera.orthographic,
            },
            width: r.width,
            height: r.height,
        })
    }
}

impl TryFrom<pb::StepRequest> for EnvStep {
    type Error = ServerError;

    fn try_from(r: pb::StepRequest) -> Result<Self> {
        Ok(EnvStep {
            env_id: r.env_id,
            action: Action {
                action_type: action_type(r.action_type)?,
                values: r.values,
                mocap_poses: r.mocap_poses,
            },
        })
    }
}

impl TryFrom<pb::StepBatchRequest> for BatchStep {
    type Error = ServerError;

    fn try_from(r: pb::StepBatchRequest) -> Result<Self> {
        Ok(BatchStep {
            batch_id: r.batch_id,
            action: Action {
                action_type: action_type(r.action_type)?,
                values: r.actions,
                mocap_poses: r.mocap_poses,
            },
            env_indices: r.env_indices,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::domain::Observed;

    #[test]
    fn action_types_are_checked() {
        let step = |action_type| {
            EnvStep::try_from(pb::StepRequest {
                env_id: "sim_1".into(),
                action_type,
                values: vec![],
                ..Default::default()
            })
        };
        assert_eq!(
            step(pb::ActionType::Velocity as i32)
                .unwrap()
                .action
                .action_type,
            ActionType::Velocity
        );
        let err = step(0).unwrap_err().to_string();
        assert!(err.contains("ACTION_TYPE_UNSPECIFIED"), "{err}");
        let err = step(9).unwrap_err().to_string();
        assert!(err.contains("unknown value 9"), "{err}");
    }

    #[test]
    fn observations_split_into_parts_along_the_env_layout() {
        let observed = |flat: Vec<f32>, floating_base, task| Observed {
            flat,
            layout: gymfleet_env::observation_layout(
                gymfleet_env::Observed {
                    dofs: if floating_base { 1 } else { 2 },
                    floating_base,
                    free_bodies: usize::from(floating_base),
                    end_effectors: 1,
                },
                task,
            )
            .into(),
        };
        let o = observation(&observed(
            vec![
                1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0, 11.0, 20.0, 0.0, 40.0,
            ],
            false,
            Some(("target", 3)),
        ));
        assert_eq!(o.joint_positions, [1.0, 2.0]);
        assert_eq!(o.joint_velocities, [3.0, 4.0]);
        assert_eq!(o.end_effector_poses.len(), 7);
        assert_eq!(o.task_observation, [20.0, 0.0, 40.0]);
        assert!(o.base_pose.is_empty() && o.base_velocity.is_empty());
        assert!(o.free_body_poses.is_empty() && o.free_body_velocities.is_empty());
        // A floating base's 13 floats, then a free body's 13, come between the joints and
        // the poses.
        let flat: Vec<f32> = (0..(1 + 1 + 13 + 13 + 7)).map(|v| v as f32).collect();
        let o = observation(&observed(flat, true, None));
        assert_eq!(o.base_pose, [2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0]);
        assert_eq!(o.base_velocity, [9.0, 10.0, 11.0, 12.0, 13.0, 14.0]);
        assert_eq!(o.free_body_poses[0], 15.0);
        assert_eq!(o.free_body_velocities, [22.0, 23.0, 24.0, 25.0, 26.0, 27.0]);
        assert_eq!(o.end_effector_poses[0], 28.0);
        assert!(o.task_observation.is_empty());
    }
}
