//! The single-environment tools of the user guide: `create_robot_env`, `gym_reset`,
//! `gym_step`, `gym_observe`, `gym_render`, `gym_save_state`, `gym_load_state` and
//! `gym_close`. Each checks what it can before calling the
//! server (ids, action count, finiteness) and answers with the guide's JSON, as structured
//! content and as text; every failure is a tool error with a message to act on.

use rmcp::handler::server::wrapper::Parameters;
use rmcp::{tool, tool_router};

use crate::actions;
use gymfleet_client::EnvState;

use crate::errors::{McpError, Result};
use crate::output::{
    EnvClosed, EnvCreated, ModelOut, ModelsOut, ObservationOut, RenderOut, StateSaved, StepOut,
};
use crate::params::{
    CreateEnvParams, EnvRefParams, LoadStateParams, MocapPoseParams, RenderParams, ResetParams,
    StepParams,
};
use crate::reply::{Json, Picture};
use crate::server::GymTools;

#[tool_router(router = env_router, vis = "pub(crate)")]
impl GymTools {
    /// Creates one physics environment from an assembly document.
    #[tool(
        description = "Create a physics environment from a robot assembly document. Returns \
        env_id (use it in gym_reset/gym_step/gym_observe/gym_close), num_joints, action_dim \
        (values per gym_step), observation_dim, end_effector_ids, dt, substeps, max_steps and \
        the joints in DOF order. Call gym_reset before stepping."
    )]
    async fn create_robot_env(
        &self,
        Parameters(p): Parameters<CreateEnvParams>,
    ) -> Result<Json<EnvCreated>> {
        let options = p.into_options()?;
        let placed = self.fleet.create_env(options).await?;
        let server = self.fleet.addr(placed.server);
        tracing::info!(env_id = %placed.id, server, "created env");
        Ok(Json(EnvCreated::new(
            placed.id.clone(),
            placed.handle.info(),
        )))
    }

    /// Resets an environment.
    #[tool(
        description = "Reset an environment to its initial state (joint positions 0, zero \
        velocities) and return the first observation: {joint_positions [deg or mm], \
        joint_velocities [deg/s or mm/s], end_effector_poses [[x, y, z, qw, qx, qy, qz], ...] \
        in mm; with a floating base also base_pose [x, y, z, qw, qx, qy, qz] and \
        base_velocity [vx, vy, vz mm/s, wx, wy, wz deg/s]}."
    )]
    async fn gym_reset(
        &self,
        Parameters(p): Parameters<ResetParams>,
    ) -> Result<Json<ObservationOut>> {
        let placed = self.fleet.env(&p.env_id)?;
        let observation = placed
            .handle
            .reset_to(p.seed, p.keyframe.as_deref().unwrap_or(""))
            .await
            .map_err(|err| self.fleet.env_failed(&placed, &err))?;
        Ok(Json(ObservationOut::from(&observation)))
    }

    /// Steps an environment.
    #[tool(
        description = "Apply one action for one step (dt seconds) and return {observation, \
        reward, done, terminated, truncated}. values holds exactly action_dim numbers in \
        document joint order: torque in N·m (revolute) or N (prismatic); position targets in \
        degrees or mm; velocity targets in degrees/s or mm/s. When done is true, call \
        gym_reset."
    )]
    async fn gym_step(&self, Parameters(p): Parameters<StepParams>) -> Result<Json<StepOut>> {
        let placed = self.fleet.env(&p.env_id)?;
        let values = actions::env_action(&placed.id, placed.handle.info().action_dim, &p.values)?;
        let result = placed
            .handle
            .step(p.action_type.into(), &values)
            .await
            .map_err(|err| self.fleet.env_failed(&placed, &err))?;
        Ok(Json(StepOut::new(
            &result,
            &placed.handle.info().term_names,
        )))
    }

    /// Moves a mocap body.
    #[tool(
        description = "Move a mocap body (create_robot_env lists them as mocap_bodies): set where \
        its frame is to be at the end of the next gym_step, and stay. position [x, y, z] in \
        world mm, quaternion [qw, qx, qy, qz] (default no rotation). What is welded or \
        connected to it follows; what it touches is pushed. Returns {}."
    )]
    async fn gym_set_mocap_pose(
        &self,
        Parameters(p): Parameters<MocapPoseParams>,
    ) -> Result<Json<serde_json::Map<String, serde_json::Value>>> {
        let placed = self.fleet.env(&p.env_id)?;
        let [x, y, z] = p.position;
        let [qw, qx, qy, qz] = p.quaternion;
        placed
            .handle
            .set_mocap_pose(&p.body, [x, y, z, qw, qx, qy, qz])
            .await
            .map_err(|err| self.fleet.env_failed(&placed, &err))?;
        Ok(Json(serde_json::Map::new()))
    }

    /// Observes an environment.
    #[tool(
        description = "Read an environment's current observation without stepping: \
        {joint_positions [deg or mm], joint_velocities [deg/s or mm/s], end_effector_poses \
        [[x, y, z, qw, qx, qy, qz], ...] in mm; with a floating base also base_pose and \
        base_velocity}."
    )]
    async fn gym_observe(
        &self,
        Parameters(p): Parameters<EnvRefParams>,
    ) -> Result<Json<ObservationOut>> {
        let placed = self.fleet.env(&p.env_id)?;
        let observation = placed
            .handle
            .observe()
            .await
            .map_err(|err| self.fleet.env_failed(&placed, &err))?;
        Ok(Json(ObservationOut::from(&observation)))
    }

    /// Renders an environment.
    #[tool(
        description = "See the robot: a PNG picture of an environment as it is now (image \
        content) plus a JSON text {width, height, grid_mm, description}. Parts are shaded \
        solids on a ground grid (line spacing grid_mm, every fifth line darker), joint axes \
        red, end effectors green, a reach target magenta. camera: iso (default), front, side \
        or top, framing the whole robot; or give eye/target in world mm.",
        output_schema = rmcp::handler::server::common::schema_for_output::<RenderOut>()
    )]
    async fn gym_render(
        &self,
        Parameters(p): Parameters<RenderParams>,
    ) -> Result<Picture<RenderOut>> {
        let placed = self.fleet.env(&p.env_id)?;
        let (camera, width, height) = p.camera();
        let image = placed
            .handle
            .render(&camera, width, height)
            .await
            .map_err(|err| self.fleet.env_failed(&placed, &err))?;
        Ok(Picture {
            png: image.png,
            about: RenderOut {
                env_id: placed.id.clone(),
                width: image.width,
                height: image.height,
                grid_mm: image.grid_mm,
                description: image.description,
            },
        })
    }

    /// Lists the server's model library.
    #[tool(
        description = "List the robot models the server has in its library: {models: [{name, \
        format, dofs, action_dim}]}. Pass a name as `model` to create_robot_env or \
        batch_create_envs instead of a document."
    )]
    async fn list_models(&self) -> Result<Json<ModelsOut>> {
        let models = self.fleet.list_models().await?;
        Ok(Json(ModelsOut {
            models: models
                .into_iter()
                .map(|m| ModelOut {
                    name: m.name,
                    format: match m.format {
                        gymfleet_client::DocumentFormat::Mjcf => "mjcf",
                        gymfleet_client::DocumentFormat::Urdf => "urdf",
                        _ => "json",
                    }
                    .to_string(),
                    dofs: m.dofs,
                    action_dim: m.action_dim,
                })
                .collect(),
        }))
    }

    /// Saves an environment's state.
    #[tool(
        description = "Save an environment's whole state (robot pose and velocities, episode, \
        task target, random generator) as an opaque base64 string. Try actions with gym_step, \
        then call gym_load_state with this state to take them back: the env continues exactly \
        as if they never happened. Returns {env_id, state, bytes}."
    )]
    async fn gym_save_state(
        &self,
        Parameters(p): Parameters<EnvRefParams>,
    ) -> Result<Json<StateSaved>> {
        use base64::Engine as _;
        let placed = self.fleet.env(&p.env_id)?;
        let state = placed
            .handle
            .save_state()
            .await
            .map_err(|err| self.fleet.env_failed(&placed, &err))?;
        Ok(Json(StateSaved {
            env_id: placed.id.clone(),
            bytes: state.len(),
            state: base64::engine::general_purpose::STANDARD.encode(state.as_bytes()),
        }))
    }

    /// Loads a saved state into an environment.
    #[tool(
        description = "Return an environment to a state saved by gym_save_state (of this env, \
        or of another env created with the same document and options) and return the \
        observation there: {joint_positions, joint_velocities, end_effector_poses, target}."
    )]
    async fn gym_load_state(
        &self,
        Parameters(p): Parameters<LoadStateParams>,
    ) -> Result<Json<ObservationOut>> {
        use base64::Engine as _;
        let placed = self.fleet.env(&p.env_id)?;
        let bytes = base64::engine::general_purpose::STANDARD
            .decode(p.state.trim())
            .map_err(|err| {
                McpError::bad_argument(format!(
                    "state: not the base64 text gym_save_state returns ({err})"
                ))
            })?;
        let observation = placed
            .handle
            .load_state(&EnvState::from_bytes(bytes))
            .await
            .map_err(|err| self.fleet.env_failed(&placed, &err))?;
        Ok(Json(ObservationOut::from(&observation)))
    }

    /// Closes an environment.
    #[tool(
        description = "Close an environment and free its resources. Its env_id is invalid \
        afterwards. Always call this when you are done."
    )]
    async fn gym_close(&self, Parameters(p): Parameters<EnvRefParams>) -> Result<Json<EnvClosed>> {
        let placed = self.fleet.env(&p.env_id)?;
        placed
            .handle
            .close()
            .await
            .map_err(|err| self.fleet.env_failed(&placed, &err))?;
        self.fleet.forget_env(&placed.id);
        tracing::info!(env_id = %placed.id, "closed env");
        Ok(Json(EnvClosed {
            env_id: placed.id,
            closed: true,
        }))
    }
}
