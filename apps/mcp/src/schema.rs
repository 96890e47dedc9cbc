//! [`one_line_descriptions`]: a schemars transform applied to every tool input and output
//! type. schemars joins the lines of a `///` comment with `\n`; agents read the schema as
//! prose, so the wrapped lines are joined back into one.

use schemars::Schema;
use serde_json::Value;

/// Replaces the line breaks of every `description` in `schema` (recursively) by spaces.
pub(crate) fn one_line_descriptions(schema: &mut Schema) {
    if let Some(object) = schema.as_object_mut() {
        for (key, value) in object.iter_mut() {
            unwrap(key, value);
        }
    }
}

fn unwrap(key: &str, value: &mut Value) {
    match value {
        Value::String(text) if key == "description" && text.contains('\n') => {
            *text = text
                .split('\n')
                .map(str::trim)
                .collect::<Vec<_>>()
                .join(" ");
        }
        Value::Object(map) => map.iter_mut().for_each(|(k, v)| unwrap(k, v)),
        Value::Array(items) => items.iter_mut().for_each(|v| unwrap("", v)),
        _ => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrapped_descriptions_become_one_line() {
        let mut schema: Schema = serde_json::from_value(serde_json::json!({
            "description": "top\nline",
            "properties": {
                "a": {"description": "one\n two", "items": [{"description": "x\ny"}]},
                "description": {"type": "string"}
            }
        }))
        .unwrap();
        one_line_descriptions(&mut schema);
        let value = schema.as_value();
        assert_eq!(value["description"], "top line");
        assert_eq!(value["properties"]["a"]["description"], "one two");
        assert_eq!(value["properties"]["a"]["items"][0]["description"], "x y");
        assert_eq!(value["properties"]["description"]["type"], "string");
    }
}
