//! The repository's seed models (`models/*.json`), compiled in so the package's
//! registered environments (`gymfleet/Arm2-v0`, …) need no files at run time.

use pyo3::exceptions::PyKeyError;
use pyo3::prelude::*;

const MODELS: [(&str, &str); 4] = [
    ("pendulum", include_str!("../../../models/pendulum.json")),
    ("arm2", include_str!("../../../models/arm2.json")),
    ("arm6", include_str!("../../../models/arm6.json")),
    ("chain20", include_str!("../../../models/chain20.json")),
];

/// The JSON text of seed model `name` (`pendulum`, `arm2`, `arm6`, `chain20`).
#[pyfunction]
pub(crate) fn seed_model(name: &str) -> PyResult<&'static str> {
    MODELS
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, json)| *json)
        .ok_or_else(|| {
            let names: Vec<&str> = MODELS.iter().map(|(n, _)| *n).collect();
            PyKeyError::new_err(format!(
                "no seed model {name:?}; there are {}",
                names.join(", ")
            ))
        })
}
