//! `gymfleet-server`: parses flags, sets up logging, and serves until SIGTERM or Ctrl-C.

use clap::Parser;
use gymfleet_server::{init_tracing, serve, Cli, Listener};

#[tokio::main]
async fn main() -> std::process::ExitCode {
    let cli = Cli::parse();
    init_tracing(cli.log_format);
    let config = match cli.server_config() {
        Ok(config) => config,
        Err(err) => {
            tracing::error!(%err, "bad configuration");
            return std::process::ExitCode::FAILURE;
        }
    };
    let listener = match Listener::bind(&cli.listen).await {
        Ok(listener) => listener,
        Err(err) => {
            tracing::error!(listen = %cli.listen, %err, "cannot listen");
            return std::process::ExitCode::FAILURE;
        }
    };
    // Ctrl-C or SIGTERM (Kubernetes stops a pod with it) starts a graceful shutdown.
    let shutdown = async {
        tokio_graceful::default_signal().await;
        tracing::info!("received Ctrl-C or SIGTERM");
    };
    match serve(listener, config, shutdown).await {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(err) => {
            tracing::error!(%err, "server failed");
            std::process::ExitCode::FAILURE
        }
    }
}
