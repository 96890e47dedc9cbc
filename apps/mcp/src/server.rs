//! [`GymTools`]: the MCP server handler. It joins the env tools (`env_tools.rs`) and the
//! batch tools (`batch_tools.rs`) into one router and tells agents, in its instructions,
//! how the tools fit together.

use std::sync::Arc;

use rmcp::handler::server::router::tool::ToolRouter;
use rmcp::model::{
    CompleteRequestMethod, CompleteRequestParams, CompleteResult, Implementation, JsonObject,
    ListPromptsRequestMethod, ListPromptsResult, ListResourceTemplatesRequestMethod,
    ListResourceTemplatesResult, ListResourcesRequestMethod, ListResourcesResult,
    PaginatedRequestParams, ServerCapabilities, ServerConfig,
};
use rmcp::service::RequestContext;
use rmcp::{tool_handler, ErrorData, RoleServer, ServerHandler};
use serde_json::Value;

use crate::fleet::Fleet;

/// What an agent is told about this server when it connects. It names every tool (a
/// test checks it against the router, and the adapter's README's tool table too).
const INSTRUCTIONS: &str = "gymfleet: physics (Rapier) gym environments built from robot \
documents: assembly JSON (parts, instances, joints; lengths in mm, angles in degrees, Z up, \
gravity -Z), or MJCF or URDF text, converted (meshes as assets_base64), or a model of the \
server's library by name (list_models, then model instead of document). Single environment: \
create_robot_env -> env_id, then gym_reset, gym_step (action_type torque [N·m or N] | \
position [deg or mm] | velocity [deg/s or mm/s], exactly action_dim values), gym_observe, \
gym_render (a PNG and a description of the view), gym_save_state and gym_load_state (try \
actions, then take them back), gym_set_mocap_pose (move a scene's mocap handle, which pulls \
what is welded to it), and gym_close when done. Many at once: batch_create_envs -> \
batch_id, then batch_step with one array of action_dim values per env, batch_reset, \
batch_close. Observations are {joint_positions, joint_velocities, end_effector_poses}, each \
pose [x, y, z, qw, qx, qy, qz] in mm, plus target with a reach task, base_pose, \
base_velocity for a floating base, and free_body_poses, free_body_velocities for objects. Rewards come from the task given to the create tools \
(reach a target, track joint targets, stay upright, or weighted terms whose values each step \
reports in terms); without a task the reward is 0.0. randomize draws masses, friction, \
damping and gains at every reset. Scale torques to the parts: masses come from volume x \
density (default 1000 kg/m^3), so a 40 mm arm weighs under a gram and 1e-4 N·m already \
swings it; position targets are the easiest way to move a small robot.";

/// The gym tools, served to one MCP session; every session shares one [`Fleet`].
#[derive(Debug, Clone)]
pub(crate) struct GymTools {
    pub(crate) fleet: Arc<Fleet>,
    tool_router: ToolRouter<GymTools>,
}

impl GymTools {
    /// The tools over `fleet`.
    pub(crate) fn new(fleet: Arc<Fleet>) -> Self {
        let mut tool_router = Self::env_router() + Self::batch_router();
        for route in tool_router.map.values_mut() {
            let tool = &mut route.attr;
            tool.input_schema = Arc::new(plain_integers(tool.input_schema.as_ref().clone()));
            if let Some(output) = &tool.output_schema {
                tool.output_schema = Some(Arc::new(plain_integers(output.as_ref().clone())));
            }
        }
        GymTools { fleet, tool_router }
    }
}

/// `schema` with schemars' non-standard integer formats (`"format": "uint32"`, `"uint"`,
/// …), which strict MCP clients warn about, replaced by standard `minimum`/`maximum`
/// bounds on a plain `"type": "integer"`.
fn plain_integers(mut schema: JsonObject) -> JsonObject {
    fn walk(value: &mut Value) {
        match value {
            Value::Object(map) => {
                let bounds = match map.get("format").and_then(Value::as_str) {
                    Some("uint8") => Some((0, Some(u64::from(u8::MAX)))),
                    Some("uint16") => Some((0, Some(u64::from(u16::MAX)))),
                    Some("uint32") => Some((0, Some(u64::from(u32::MAX)))),
                    Some("uint64" | "uint") => Some((0, None)),
                    _ => None,
                };
                if let Some((min, max)) = bounds {
                    map.remove("format");
                    let keep_min = map.get("minimum").and_then(Value::as_u64).unwrap_or(min);
                    map.insert("minimum".into(), Value::from(keep_min.max(min)));
                    if let Some(max) = max {
                        map.entry("maximum").or_insert(Value::from(max));
                    }
                }
                map.values_mut().for_each(walk);
            }
            Value::Array(items) => items.iter_mut().for_each(walk),
            _ => {}
        }
    }
    schema.values_mut().for_each(walk);
    schema
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

    // Only tools are declared, so every other capability's methods answer
    // "method not found", the listings as well as the reads (rmcp's defaults answer the
    // listings with empty lists but the reads with an error).

    async fn list_resources(
        &self,
        _request: Option<PaginatedRequestParams>,
        _context: RequestContext<RoleServer>,
    ) -> Result<ListResourcesResult, ErrorData> {
        Err(ErrorData::method_not_found::<ListResourcesRequestMethod>())
    }

    async fn list_resource_templates(
        &self,
        _request: Option<PaginatedRequestParams>,
        _context: RequestContext<RoleServer>,
    ) -> Result<ListResourceTemplatesResult, ErrorData> {
        Err(ErrorData::method_not_found::<
            ListResourceTemplatesRequestMethod,
        >())
    }

    async fn list_prompts(
        &self,
        _request: Option<PaginatedRequestParams>,
        _context: RequestContext<RoleServer>,
    ) -> Result<ListPromptsResult, ErrorData> {
        Err(ErrorData::method_not_found::<ListPromptsRequestMethod>())
    }

    async fn complete(
        &self,
        _request: CompleteRequestParams,
        _context: RequestContext<RoleServer>,
    ) -> Result<CompleteResult, ErrorData> {
        Err(ErrorData::method_not_found::<CompleteRequestMethod>())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integer_formats_become_bounds() {
        let schema = serde_json::json!({
            "type": "object",
            "properties": {
                "n_envs": {"type": "integer", "format": "uint32", "minimum": 1},
                "seed": {"type": ["integer", "null"], "format": "uint64", "minimum": 0},
                "index": {"type": "integer", "format": "uint"},
                "dt": {"type": "number", "format": "double"},
                "nested": {"anyOf": [{"type": "integer", "format": "uint16"}]}
            }
        });
        let Value::Object(schema) = schema else {
            unreachable!()
        };
        let plain = Value::Object(plain_integers(schema));
        assert_eq!(
            plain,
            serde_json::json!({
                "type": "object",
                "properties": {
                    "n_envs": {"type": "integer", "minimum": 1, "maximum": 4294967295u64},
                    "seed": {"type": ["integer", "null"], "minimum": 0},
                    "index": {"type": "integer", "minimum": 0},
                    "dt": {"type": "number", "format": "double"},
                    "nested": {"anyOf": [{"type": "integer", "minimum": 0, "maximum": 65535}]}
                }
            })
        );
    }

    /// Every tool the router serves is named in the instructions and has a row in the
    /// adapter's README's tool table, and no row names a tool that does not exist (the
    /// top-level README links to that table).
    #[test]
    fn the_instructions_and_the_readmes_name_every_tool() {
        let router = GymTools::env_router() + GymTools::batch_router();
        let mut names: Vec<String> = router
            .list_all()
            .iter()
            .map(|t| t.name.to_string())
            .collect();
        names.sort();
        let text = include_str!("../README.md");
        let mut rows: Vec<String> = text
            .lines()
            .filter_map(|l| l.strip_prefix("| `"))
            .filter_map(|l| l.split_once("` |").map(|(name, _)| name.to_string()))
            .filter(|name| {
                name.starts_with("gym_") || name.starts_with("batch_") || names.contains(name)
            })
            .filter(|name| !name.starts_with("gymfleet"))
            .collect();
        rows.sort();
        rows.dedup();
        assert_eq!(rows, names, "apps/mcp/README.md's tool table");
        for name in &names {
            assert!(
                INSTRUCTIONS.contains(name.as_str()),
                "the instructions lack {name}"
            );
        }
    }
}
