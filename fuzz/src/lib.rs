//! gymfleet's fuzz targets: see `targets.rs` (documents, descriptions, assets, saved
//! states), `requests.rs` (the server's requests), `mcp.rs` (the MCP adapter) and
//! `README.md`.
//!
//! The targets cover the doors that take a client's bytes: `targets.rs` assembly JSON,
//! MJCF, URDF, asset archives, saved states and their fields past the checksum;
//! `requests.rs` `CreateEnvRequest` and `StepBatchRequest` through `DirectService`;
//! `mcp.rs` MCP messages through the adapter's session. Each asserts that what validates
//! builds and steps, that no call ends INTERNAL or hangs, and that errors stay bounded.
//! Their seed corpora are in `corpus/<target>/`, and the runs so far in `README.md`. The
//! crate is excluded from the root workspace, with its own lock file and the same
//! `[patch.crates-io]`, and is built on the stable toolchain with `RUSTC_BOOTSTRAP=1`.
//! `tests/tests/fuzz_corpora.rs` replays the corpora as an ordinary test.

pub mod mcp;
pub mod requests;
pub mod targets;
