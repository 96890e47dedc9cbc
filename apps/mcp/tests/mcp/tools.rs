//! The tool list: the guide's names, and input schemas an agent can act on (a
//! description on every property, the right required fields), plus output schemas.

use serde_json::Value;

use crate::Adapter;

const TOOLS: [&str; 14] = [
    "batch_close",
    "batch_create_envs",
    "batch_reset",
    "batch_step",
    "create_robot_env",
    "gym_close",
    "gym_load_state",
    "gym_observe",
    "gym_render",
    "gym_reset",
    "gym_save_state",
    "gym_set_mocap_pose",
    "gym_step",
    "list_models",
];

/// Asserts a description on every property of `schema`, recursively.
fn assert_described(tool: &str, path: &str, schema: &Value) {
    let Some(properties) = schema.get("properties").and_then(Value::as_object) else {
        return;
    };
    for (name, property) in properties {
        let description = property
            .get("description")
            .and_then(Value::as_str)
            .unwrap_or_default();
        assert!(
            description.len() > 10,
            "{tool}: property {path}{name} has no useful description: {property}"
        );
        assert!(
            !description.contains('\n'),
            "{tool}: {path}{name}: {description:?}"
        );
        assert_described(tool, &format!("{path}{name}."), property);
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn tools_are_listed_with_described_schemas() {
    let adapter = Adapter::embedded().await;
    let info = adapter.session.peer_info().expect("server info");
    let implementation = info.server_info.as_ref().expect("implementation");
    assert_eq!(implementation.name, "gymfleet-mcp");
    assert!(info
        .instructions
        .as_deref()
        .unwrap_or_default()
        .contains("create_robot_env"));

    let tools = adapter.session.list_all_tools().await.expect("tools/list");
    let mut names: Vec<&str> = tools.iter().map(|t| t.name.as_ref()).collect();
    names.sort_unstable();
    assert_eq!(names, TOOLS);

    for tool in &tools {
        let name = tool.name.as_ref();
        assert!(
            tool.description.as_deref().unwrap_or_default().len() > 40,
            "{name}: short description"
        );
        let schema = Value::Object((*tool.input_schema).clone());
        assert_eq!(schema["type"], "object", "{name}");
        assert_described(name, "", &schema);
        let output = tool
            .output_schema
            .as_ref()
            .unwrap_or_else(|| panic!("{name}: no output schema"));
        assert_eq!(output.get("type"), Some(&Value::from("object")), "{name}");
        let output = Value::Object((**output).clone());
        for (side, schema) in [("input", &schema), ("output", &output)] {
            let text = schema.to_string();
            assert!(
                !text.contains("\"format\":\"uint") && !text.contains("\"format\":\"int"),
                "{name}: {side} schema has a non-standard integer format: {text}"
            );
        }
    }
    let n_envs = &tools
        .iter()
        .find(|t| t.name == "batch_create_envs")
        .expect("batch_create_envs")
        .input_schema["properties"]["n_envs"];
    assert_eq!(n_envs["type"], "integer");
    assert_eq!(n_envs["maximum"], u32::MAX);

    let required = |name: &str| -> Vec<String> {
        let tool = tools.iter().find(|t| t.name == name).expect("tool");
        // No "required" list at all means nothing is required.
        let mut required: Vec<String> = tool
            .input_schema
            .get("required")
            .and_then(|r| r.as_array())
            .cloned()
            .unwrap_or_default()
            .iter()
            .map(|v| v.as_str().expect("name").to_string())
            .collect();
        required.sort_unstable();
        required
    };
    let none: [&str; 0] = [];
    assert_eq!(required("create_robot_env"), none, "document or model");
    assert_eq!(required("gym_reset"), ["env_id"]);
    assert_eq!(required("gym_step"), ["action_type", "env_id", "values"]);
    assert_eq!(required("gym_observe"), ["env_id"]);
    assert_eq!(required("gym_close"), ["env_id"]);
    assert_eq!(required("gym_render"), ["env_id"]);
    assert_eq!(required("gym_save_state"), ["env_id"]);
    assert_eq!(required("gym_load_state"), ["env_id", "state"]);
    assert_eq!(required("batch_create_envs"), ["n_envs"]);
    assert_eq!(
        required("batch_step"),
        ["action_type", "actions", "batch_id"]
    );
    assert_eq!(required("batch_reset"), ["batch_id"]);
    assert_eq!(required("batch_close"), ["batch_id"]);

    let step = tools
        .iter()
        .find(|t| t.name == "gym_step")
        .expect("gym_step");
    let action_type = &step.input_schema["properties"]["action_type"];
    assert_eq!(
        action_type["enum"],
        serde_json::json!(["torque", "position", "velocity"])
    );
    let units = action_type["description"].as_str().expect("description");
    for unit in ["N·m", "degrees", "mm"] {
        assert!(
            units.contains(unit),
            "action_type description lacks {unit}: {units}"
        );
    }
    let create = tools
        .iter()
        .find(|t| t.name == "create_robot_env")
        .expect("create_robot_env");
    assert_eq!(
        create.input_schema["properties"]["document"]["type"],
        serde_json::json!(["object", "string", "null"]),
        "optional: a document or a model"
    );
    assert_eq!(
        create.input_schema["properties"]["model"]["type"],
        serde_json::json!(["string", "null"])
    );
    adapter.stop().await;
}

/// Only tools are declared: the other capabilities' methods answer "method not found"
/// alike, listings included (an empty listing would promise a capability that a read
/// then denies).
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn undeclared_capabilities_are_method_not_found() {
    let adapter = Adapter::embedded().await;
    let capabilities = &adapter.session.peer_info().expect("info").capabilities;
    assert!(capabilities.tools.is_some());
    assert!(capabilities.resources.is_none() && capabilities.prompts.is_none());
    let peer = adapter.session.peer();
    let not_found = |result: Result<_, rmcp::ServiceError>, method: &str| match result {
        Err(rmcp::ServiceError::McpError(e)) => {
            assert_eq!(e.code, rmcp::model::ErrorCode::METHOD_NOT_FOUND, "{method}");
            assert_eq!(e.message, method);
        }
        other => panic!("{method}: expected method not found, got {other:?}"),
    };
    not_found(
        peer.list_resources(None).await.map(|_| ()),
        "resources/list",
    );
    not_found(
        peer.list_resource_templates(None).await.map(|_| ()),
        "resources/templates/list",
    );
    not_found(
        peer.read_resource(rmcp::model::ReadResourceRequestParams::new("gymfleet://x"))
            .await
            .map(|_| ()),
        "resources/read",
    );
    not_found(peer.list_prompts(None).await.map(|_| ()), "prompts/list");
    adapter.stop().await;
}
