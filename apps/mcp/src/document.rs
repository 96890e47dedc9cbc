//! [`Document`]: the `document` input of the create tools. Agents pass the assembly
//! either as a JSON object or as a string holding the JSON (or MJCF text, which the
//! server detects and converts); both become the text the server parses (and reports
//! errors in, with their JSON paths, or an MJCF element and line).

use std::borrow::Cow;

use schemars::{json_schema, JsonSchema, Schema, SchemaGenerator};
use serde::Deserialize;
use serde_json::Value;

use crate::errors::{McpError, Result};

/// An assembly document as given: an object, or a string containing one.
#[derive(Debug, Clone, Deserialize)]
#[serde(transparent)]
pub(crate) struct Document(Value);

impl Document {
    /// The JSON text to send to the server. A string is passed through untouched (the
    /// server reports where it fails to parse); other non-objects are refused here.
    pub(crate) fn into_json_text(self) -> Result<String> {
        match self.0 {
            Value::String(text) => Ok(text),
            object @ Value::Object(_) => Ok(object.to_string()),
            other => Err(McpError::bad_argument(format!(
                "document must be the assembly document as a JSON object (with \"parts\" and \
                 \"assembly\"), or a string containing that JSON; got {}",
                kind(&other)
            ))),
        }
    }
}

fn kind(value: &Value) -> &'static str {
    match value {
        Value::Null => "null",
        Value::Bool(_) => "a boolean",
        Value::Number(_) => "a number",
        Value::String(_) => "a string",
        Value::Array(_) => "an array",
        Value::Object(_) => "an object",
    }
}

impl JsonSchema for Document {
    fn schema_name() -> Cow<'static, str> {
        "Document".into()
    }

    fn inline_schema() -> bool {
        true
    }

    fn json_schema(_: &mut SchemaGenerator) -> Schema {
        json_schema!({
            "type": ["object", "string"],
            "description": "An assembly document: a JSON object, or a string containing it; or a MuJoCo MJCF description (XML text), which the server converts."
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn doc(value: Value) -> std::result::Result<String, String> {
        serde_json::from_value::<Document>(value)
            .unwrap()
            .into_json_text()
            .map_err(|e| e.to_string())
    }

    #[test]
    fn objects_and_strings_become_json_text() {
        let object = doc(serde_json::json!({"parts": []})).unwrap();
        assert_eq!(object, r#"{"parts":[]}"#);
        assert_eq!(
            doc(Value::String("{ not json".into())).unwrap(),
            "{ not json"
        );
    }

    #[test]
    fn other_values_say_what_was_expected() {
        let err = doc(serde_json::json!([1, 2])).unwrap_err();
        assert!(err.contains("JSON object"), "{err}");
        assert!(err.ends_with("got an array"), "{err}");
        assert!(doc(Value::Null).unwrap_err().ends_with("got null"));
    }
}
