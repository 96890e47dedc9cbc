//! Action inputs checked before any call: [`ActionValue`] (a JSON number, or a string or
//! null that an agent sent by mistake, kept so the error can say what it got), and the
//! shape checks against the handle's `action_dim`, phrased with the adapter's ids.

use std::fmt;

use serde::de::{self, Deserializer, Visitor};
use serde::Deserialize;

use crate::errors::{McpError, Result};

/// One action value as sent. Numbers are the norm; `"NaN"`, `"inf"` or `null` are
/// accepted by the parser only so that the check can refuse them by name.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum ActionValue {
    /// A JSON number.
    Number(f64),
    /// A JSON string (it may spell a number, `NaN` or `inf`).
    Text(String),
    /// JSON `null`.
    Null,
}

/// Why an action value is not a finite 32-bit float.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
enum NotFinite {
    #[error("is null")]
    Null,
    #[error("is the string {0:?}, not a number")]
    Text(String),
    #[error("is NaN")]
    NaN,
    #[error("is infinite ({0})")]
    Infinite(f64),
    #[error("= {0:e} is out of range (actions are 32-bit floats, at most about 3.4e38)")]
    OutOfRange(f64),
}

impl ActionValue {
    /// The value as the wire's `f32`, or why it is not a finite one.
    fn to_f32(&self) -> Result<f32, NotFinite> {
        let value = match self {
            ActionValue::Number(v) => *v,
            ActionValue::Null => return Err(NotFinite::Null),
            ActionValue::Text(text) => match text.trim().parse::<f64>() {
                Ok(v) if !v.is_finite() => v,
                _ => return Err(NotFinite::Text(text.clone())),
            },
        };
        if value.is_nan() {
            return Err(NotFinite::NaN);
        }
        if value.is_infinite() {
            return Err(NotFinite::Infinite(value));
        }
        let narrowed = value as f32;
        if narrowed.is_infinite() {
            return Err(NotFinite::OutOfRange(value));
        }
        Ok(narrowed)
    }
}

impl<'de> Deserialize<'de> for ActionValue {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct ValueVisitor;

        impl Visitor<'_> for ValueVisitor {
            type Value = ActionValue;

            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a number")
            }

            fn visit_f64<E: de::Error>(self, v: f64) -> Result<ActionValue, E> {
                Ok(ActionValue::Number(v))
            }

            fn visit_i64<E: de::Error>(self, v: i64) -> Result<ActionValue, E> {
                Ok(ActionValue::Number(v as f64))
            }

            fn visit_u64<E: de::Error>(self, v: u64) -> Result<ActionValue, E> {
                Ok(ActionValue::Number(v as f64))
            }

            fn visit_str<E: de::Error>(self, v: &str) -> Result<ActionValue, E> {
                Ok(ActionValue::Text(v.to_string()))
            }

            fn visit_unit<E: de::Error>(self) -> Result<ActionValue, E> {
                Ok(ActionValue::Null)
            }

            fn visit_none<E: de::Error>(self) -> Result<ActionValue, E> {
                Ok(ActionValue::Null)
            }
        }

        deserializer.deserialize_any(ValueVisitor)
    }
}

const FINITE: &str = "every action value must be a finite number";

fn plural(n: usize, word: &str) -> String {
    if n == 1 {
        format!("{n} {word}")
    } else {
        format!("{n} {word}s")
    }
}

/// Checks one env's action against its `action_dim` and converts it for the wire.
pub(crate) fn env_action(
    env_id: &str,
    action_dim: usize,
    values: &[ActionValue],
) -> Result<Vec<f32>> {
    if values.len() != action_dim {
        return Err(McpError::bad_argument(format!(
            "{env_id} expects {} (action_dim), got {}",
            plural(action_dim, "action value"),
            values.len()
        )));
    }
    values
        .iter()
        .enumerate()
        .map(|(i, v)| {
            v.to_f32()
                .map_err(|why| McpError::bad_argument(format!("values[{i}] {why}; {FINITE}")))
        })
        .collect()
}

/// Checks a batch's actions (one array per env) and flattens them row-major.
pub(crate) fn batch_actions(
    batch_id: &str,
    n_envs: usize,
    action_dim: usize,
    actions: &[Vec<ActionValue>],
) -> Result<Vec<f32>> {
    let shape = format!(
        "{batch_id} expects {} of {}",
        plural(n_envs, "array"),
        plural(action_dim, "value")
    );
    if actions.len() != n_envs {
        return Err(McpError::bad_argument(format!(
            "{shape} (one array per env, action_dim values each); got {}",
            plural(actions.len(), "array")
        )));
    }
    if let Some((env, row)) = actions
        .iter()
        .enumerate()
        .find(|(_, row)| row.len() != action_dim)
    {
        return Err(McpError::bad_argument(format!(
            "{shape}; array {env} has {}",
            row.len()
        )));
    }
    let mut flat = Vec::with_capacity(n_envs * action_dim);
    for (env, row) in actions.iter().enumerate() {
        for (i, v) in row.iter().enumerate() {
            let value = v.to_f32().map_err(|why| {
                McpError::bad_argument(format!("actions[{env}][{i}] {why}; {FINITE}"))
            })?;
            flat.push(value);
        }
    }
    Ok(flat)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn values(json: &str) -> Vec<ActionValue> {
        serde_json::from_str(json).unwrap()
    }

    #[test]
    fn counts_are_expected_vs_got() {
        let err = env_action("sim_3", 2, &values("[1, 2, 3]"))
            .unwrap_err()
            .to_string();
        assert_eq!(err, "sim_3 expects 2 action values (action_dim), got 3");
        let err = env_action("sim_1", 1, &values("[]"))
            .unwrap_err()
            .to_string();
        assert_eq!(err, "sim_1 expects 1 action value (action_dim), got 0");
        assert_eq!(
            env_action("sim_1", 2, &values("[0.5, -1]")),
            Ok(vec![0.5, -1.0])
        );
    }

    #[test]
    fn non_finite_values_are_named() {
        let err = env_action("sim_1", 2, &values(r#"[0, "NaN"]"#))
            .unwrap_err()
            .to_string();
        assert_eq!(
            err,
            "values[1] is NaN; every action value must be a finite number"
        );
        let err = env_action("sim_1", 1, &values("[null]"))
            .unwrap_err()
            .to_string();
        assert!(err.starts_with("values[0] is null;"), "{err}");
        let err = env_action("sim_1", 1, &values(r#"["-inf"]"#))
            .unwrap_err()
            .to_string();
        assert!(err.starts_with("values[0] is infinite (-inf);"), "{err}");
        let err = env_action("sim_1", 1, &values("[1e39]"))
            .unwrap_err()
            .to_string();
        assert!(err.contains("out of range"), "{err}");
        let err = env_action("sim_1", 1, &values(r#"["0.5"]"#))
            .unwrap_err()
            .to_string();
        assert!(err.contains("the string \"0.5\", not a number"), "{err}");
    }

    #[test]
    fn batches_name_the_array_at_fault() {
        let mut rows = vec![values("[0, 0]"); 16];
        assert_eq!(batch_actions("batch_1", 16, 2, &rows).unwrap().len(), 32);
        rows[4] = values("[0, 0, 0]");
        let err = batch_actions("batch_1", 16, 2, &rows)
            .unwrap_err()
            .to_string();
        assert_eq!(err, "batch_1 expects 16 arrays of 2 values; array 4 has 3");
        rows.truncate(3);
        let err = batch_actions("batch_1", 16, 2, &rows)
            .unwrap_err()
            .to_string();
        assert_eq!(
            err,
            "batch_1 expects 16 arrays of 2 values (one array per env, action_dim values \
             each); got 3 arrays"
        );
        let rows = vec![values("[0]"), values(r#"["inf"]"#)];
        let err = batch_actions("batch_2", 2, 1, &rows)
            .unwrap_err()
            .to_string();
        assert!(err.starts_with("actions[1][0] is infinite (inf);"), "{err}");
    }
}
