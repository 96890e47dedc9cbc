//! gymfleet's fuzz targets: see `targets.rs` (documents, descriptions, assets, saved
//! states), `requests.rs` (the server's requests), `mcp.rs` (the MCP adapter) and
//! `README.md`.

pub mod mcp;
pub mod requests;
pub mod targets;
