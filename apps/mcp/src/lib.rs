//! `gymfleet-mcp`: the MCP adapter of gymfleet. It owns the MCP face of the simulator:
//! the user guide's tools (`create_robot_env`, `gym_reset`, `gym_step`, `gym_observe`,
//! `gym_close`, `batch_create_envs`, `batch_step`, `batch_reset`, `batch_close`), their
//! input and output schemas, client-side checks with agent-readable tool errors, the
//! adapter's own `sim_<n>` / `batch_<n>` ids, placement across several servers, and the
//! stdio and streamable-HTTP transports.
//!
//! It leaves simulation to gymfleet servers, reached only through `gymfleet-client` over
//! gRPC: the ones given with `--server`, or one embedded in this process on loopback
//! (feature `embedded`, on by default). It never links the physics directly.
//!
//! The binary (`src/main.rs`) only calls [`main`]; [`serve_session`] serves one session on
//! any byte stream (the fuzz target of `fuzz/` drives it over an in-memory pipe).
//!
//! # Modules
//!
//! Beside the guide's nine tools the adapter has five more: `gym_set_mocap_pose`,
//! `gym_render`, `list_models`, `gym_save_state` and `gym_load_state` (14 in all). The
//! create tools take a `task` (`task.rs`); every tool answers guide-shaped JSON (structured
//! content plus the same text) with input and output schemas that describe every field
//! (`params.rs`: `batch_create_envs` flattens `create_robot_env`'s options; `output.rs`:
//! both create tools flatten one `EnvShape`; `schema.rs`). The tools are in `env_tools.rs`
//! and `batch_tools.rs`; tool errors an agent can act on are one `thiserror` enum,
//! `McpError` (`errors.rs`). Stdio is the default transport (logs on stderr), streamable
//! HTTP comes with `--http` (`transport.rs`). The adapter holds its own id table
//! (`sim_<n>`, `batch_<n>`) mapped to client handles on one or several `--server`s
//! (`servers.rs`, `fleet.rs`). `conformance/run.sh` runs the official MCP conformance suite
//! (npm) against the adapter; CI runs it.
//!
//! # Why `embedded` is a default feature
//!
//! `embedded` stays a default feature of the adapter and of the load client on purpose: the
//! first thing a new user or an agent host does is run the tool with no flags, and it must
//! work without a server running somewhere (one command, docs/design.md §1). The cost is
//! build time and binary size, paid only by those who do not opt out; deployments that
//! always pass `--server` build with `--no-default-features`, and CI builds and tests that
//! path (`.ci/run`).

mod actions;
mod batch_tools;
mod cli;
mod document;
mod env_tools;
mod errors;
mod fleet;
mod output;
mod params;
mod reply;
mod schema;
mod server;
mod servers;
mod task;
mod transport;

use std::process::ExitCode;
use std::sync::Arc;
use std::time::Duration;

use clap::Parser;
use rmcp::ServiceExt;
use tokio::io::{AsyncRead, AsyncWrite};

use crate::cli::Cli;
use crate::errors::McpError;
use crate::fleet::Fleet;
use crate::servers::Servers;

/// The `gymfleet-mcp` command: parses the command line, serves, and says how it ended.
pub fn main() -> ExitCode {
    let cli = Cli::parse();
    cli::init_tracing(&cli.log);
    let runtime = match tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
    {
        Ok(runtime) => runtime,
        Err(err) => {
            eprintln!("gymfleet-mcp: cannot start the async runtime: {err}");
            return ExitCode::FAILURE;
        }
    };
    let outcome = runtime.block_on(run(cli));
    // A blocking stdin read may still be pending; do not wait for it.
    runtime.shutdown_timeout(Duration::from_secs(1));
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("gymfleet-mcp: {message}");
            ExitCode::FAILURE
        }
    }
}

/// Starts the servers, serves MCP until the client leaves or a signal, then closes what
/// the adapter created and stops an embedded server.
async fn run(cli: Cli) -> Result<(), McpError> {
    if let Some(addr) = cli.http {
        transport::check_http_addr(addr, cli.http_token.is_some())?;
    }
    let servers = Servers::start(&cli).await?;
    let fleet = Arc::new(Fleet::new(servers.addrs(), cli.connect.builder("")));
    tracing::info!(servers = ?fleet.addrs(), "gymfleet-mcp ready");
    let served = match cli.http {
        Some(addr) => transport::serve_http(addr, cli.http_token.clone(), Arc::clone(&fleet)).await,
        None => transport::serve_stdio(Arc::clone(&fleet)).await,
    };
    fleet.close_all().await;
    servers.stop().await;
    served
}

/// Serves one MCP session on `io` (a pipe, a socket, an in-memory duplex) with the gym
/// tools over the gymfleet servers at `addrs`, connected with `settings`, until the
/// client leaves; then closes every env and batch the session created. An error says why
/// the session could not start.
pub async fn serve_session<T>(
    addrs: Vec<String>,
    settings: gymfleet_client::ClientBuilder,
    io: T,
) -> Result<(), String>
where
    T: AsyncRead + AsyncWrite + Send + Unpin + 'static,
{
    let fleet = Arc::new(Fleet::new(addrs, settings));
    let served = match server::GymTools::new(Arc::clone(&fleet)).serve(io).await {
        Ok(service) => service
            .waiting()
            .await
            .map(|_| ())
            .map_err(|e| format!("MCP session task failed: {e}")),
        Err(e) => Err(format!("MCP initialisation failed: {e}")),
    };
    fleet.close_all().await;
    served
}
