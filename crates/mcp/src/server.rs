//! [`GymTools`]: the MCP server handler. It joins the env tools (`env_tools.rs`) and the
//! batch tools (`batch_tools.rs`) into one router and tells agents, in its instructions,
//! how the tools fit together.

use std::sync::Arc;

use rmcp::handler::server::router::tool::ToolRouter;
use rmcp::model::{Implementation, ServerCapabilities, ServerConfig};
use rmcp::{tool_handler, ServerHandler};

use crate::fleet::Fleet;

/// What an agent is told about this server when it connects.
const INSTRUCTIONS: &str = "gymfleet: physics (Rapier) gym environments built from robot \
assembly documents (JSON parts, instances and joints; lengths in mm, angles in degrees, Z up, \
gravity -Z). Single environment: create_robot_env -> env_id, then gym_reset, gym_step \
(action_type torque [N·m or N] | position [deg or mm] | velocity [deg/s or mm/s], exactly \
action_dim values), gym_observe, and gym_close when done. Many at once: batch_create_envs -> \
batch_id, then batch_step with one array of action_dim values per env, batch_reset, \
batch_close. Observations are {joint_positions, joint_velocities, end_effector_poses}, each \
pose [x, y, z, qw, qx, qy, qz] in mm. reward is 0.0: compute your own from the observation. Scale torques to the parts: masses come from volume x density (default 1000 kg/m^3), so a 40 mm arm weighs under a gram and 1e-4 N·m already swings it; position targets are the easiest way to move a small robot.";

/// The gym tools, served to one MCP session; every session shares one [`Fleet`].
#[derive(Debug, Clone)]
pub(crate) struct GymTools {
    pub(crate) fleet: Arc<Fleet>,
    tool_router: ToolRouter<GymTools>,
}

impl GymTools {
    /// The tools over `fleet`.
    pub(crate) fn new(fleet: Arc<Fleet>) -> Self {
        GymTools {
            fleet,
            tool_router: Self::env_router() + Self::batch_router(),
        }
    }
}

#[tool_handler(router = self.tool_router)]
impl ServerHandler for GymTools {
    fn get_info(&self) -> ServerConfig {
        ServerConfig::new(ServerCapabilities::builder().enable_tools().build())
            .with_server_info(Implementation::new(
                "gymfleet-mcp",
                env!("CARGO_PKG_VERSION"),
            ))
            .with_instructions(INSTRUCTIONS)
    }
}
