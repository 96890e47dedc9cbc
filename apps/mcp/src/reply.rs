//! [`Json`]: how a tool's output becomes its `CallToolResult`: the value as structured
//! content, and the same JSON as text content, its fields in declaration order (the
//! guide's order: `env_id` first, `observation` before `reward`), which a JSON object
//! map would sort. Named `Json` so that rmcp's `#[tool]` derives the output schema from
//! `Result<Json<T>, String>` as it does for its own wrapper.

use rmcp::handler::server::tool::IntoCallToolResult;
use rmcp::model::{CallToolResponse, CallToolResult, ContentBlock};
use rmcp::ErrorData;
use serde::Serialize;

/// A tool's successful output.
#[derive(Debug, Clone)]
pub(crate) struct Json<T>(pub(crate) T);

impl<T: Serialize> IntoCallToolResult for Json<T> {
    fn into_call_tool_result(self) -> Result<CallToolResponse, ErrorData> {
        let failed = |e: serde_json::Error| {
            ErrorData::internal_error(format!("cannot serialise the tool output: {e}"), None)
        };
        let text = serde_json::to_string(&self.0).map_err(failed)?;
        let value = serde_json::to_value(&self.0).map_err(failed)?;
        let mut result = CallToolResult::structured(value);
        result.content = vec![ContentBlock::text(text)];
        Ok(result.into())
    }
}

/// A picture: the PNG as MCP image content, then a JSON text with its size and what it
/// shows (camera, grid spacing, marker colours, positions).
#[derive(Debug, Clone)]
pub(crate) struct Picture<T> {
    pub(crate) png: Vec<u8>,
    pub(crate) about: T,
}

impl<T: Serialize> IntoCallToolResult for Picture<T> {
    fn into_call_tool_result(self) -> Result<CallToolResponse, ErrorData> {
        use base64::Engine as _;
        let failed = |e: serde_json::Error| {
            ErrorData::internal_error(format!("cannot serialise the tool output: {e}"), None)
        };
        let text = serde_json::to_string(&self.about).map_err(failed)?;
        let value = serde_json::to_value(&self.about).map_err(failed)?;
        let data = base64::engine::general_purpose::STANDARD.encode(&self.png);
        let mut result = CallToolResult::structured(value);
        result.content = vec![
            ContentBlock::image(data, "image/png"),
            ContentBlock::text(text),
        ];
        Ok(result.into())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Serialize)]
    struct Created {
        env_id: &'static str,
        action_dim: u32,
    }

    #[test]
    fn text_keeps_field_order_and_matches_the_structured_content() {
        let response = Json(Created {
            env_id: "sim_1",
            action_dim: 1,
        })
        .into_call_tool_result()
        .unwrap();
        let CallToolResponse::Complete(result) = response else {
            panic!("not a complete result");
        };
        let text = &result.content[0].as_text().unwrap().text;
        assert_eq!(text, r#"{"env_id":"sim_1","action_dim":1}"#);
        let parsed: serde_json::Value = serde_json::from_str(text).unwrap();
        assert_eq!(Some(parsed), result.structured_content);
        assert_eq!(result.is_error, Some(false));
    }
}
