//! gymfleet's fuzz targets: see `targets.rs` and `README.md`.

pub mod targets;
