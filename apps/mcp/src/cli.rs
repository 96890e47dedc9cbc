//! The command line ([`Cli`], clap derive, every flag also read from a `GYMFLEET_…`
//! variable) and the stderr-only log setup. Nothing here touches stdout: in stdio mode
//! stdout carries JSON-RPC and nothing else.

use std::net::SocketAddr;

use clap::Parser;
use gymfleet_client::ConnectArgs;
use tracing_subscriber::EnvFilter;

/// `gymfleet-mcp`: the gymfleet gym tools over MCP.
#[derive(Debug, Clone, Parser)]
#[command(
    name = "gymfleet-mcp",
    version,
    about = "MCP adapter for gymfleet: create_robot_env, gym_step, batch_step and the other \
             gym tools, served over stdio (default) or streamable HTTP."
)]
pub(crate) struct Cli {
    /// gymfleet server to use, as HOST:PORT, http://HOST:PORT or unix:/path/to/socket.
    /// Repeat the flag or separate addresses with commas for several servers: new envs
    /// and batches go to the
    /// server holding the fewest of this adapter's envs. Without it, an embedded server is
    /// started on 127.0.0.1 with a free port.
    #[arg(
        long = "server",
        env = "GYMFLEET_SERVER",
        value_name = "ADDR",
        value_delimiter = ','
    )]
    pub(crate) servers: Vec<String>,

    /// Serve MCP over streamable HTTP at http://ADDR/mcp instead of stdio. ADDR must be a
    /// loopback address; port 0 picks a free port. The bound URL is printed on stderr as
    /// `gymfleet-mcp: listening on http://ADDR/mcp`.
    #[arg(long, env = "GYMFLEET_MCP_HTTP", value_name = "ADDR")]
    pub(crate) http: Option<SocketAddr>,

    /// Require `Authorization: Bearer TOKEN` on every HTTP request to /mcp. With a
    /// token, --http may listen off loopback (the token travels in plain text: put a TLS
    /// proxy in front).
    #[arg(
        long,
        env = "GYMFLEET_MCP_HTTP_TOKEN",
        value_name = "TOKEN",
        hide_env_values = true,
        requires = "http"
    )]
    pub(crate) http_token: Option<String>,

    /// How to reach --server servers that require a token or TLS.
    #[command(flatten)]
    pub(crate) connect: ConnectArgs,

    /// Log filter, in tracing's EnvFilter syntax (e.g. `info`, `gymfleet_mcp=debug`).
    /// Logs always go to stderr.
    #[arg(
        long,
        env = "GYMFLEET_MCP_LOG",
        value_name = "FILTER",
        default_value = "info,rmcp=warn"
    )]
    pub(crate) log: String,

    /// Worker threads of the embedded server's simulation pool; 0 = one per core.
    /// Ignored with --server.
    #[cfg(feature = "embedded")]
    #[arg(long, env = "GYMFLEET_THREADS", value_name = "N", default_value_t = 0)]
    pub(crate) threads: usize,

    /// A model library for the embedded server (the server's `--models DIR`: `.json`,
    /// `.xml`, `.mjcf` and `.urdf` files, meshes below), listed by `list_models`.
    /// Ignored with --server.
    #[cfg(feature = "embedded")]
    #[arg(long, env = "GYMFLEET_MODELS", value_name = "DIR")]
    pub(crate) models: Option<std::path::PathBuf>,
}

impl Cli {
    /// The server addresses given, trimmed, without empty entries (an empty
    /// `GYMFLEET_SERVER` means "none").
    pub(crate) fn server_addrs(&self) -> Vec<String> {
        self.servers
            .iter()
            .map(|s| s.trim().to_string())
            .filter(|s| !s.is_empty())
            .collect()
    }
}

/// Sends logs to stderr, filtered by `filter` (falling back to `info` if it does not parse).
pub(crate) fn init_tracing(filter: &str) {
    let filter = EnvFilter::try_new(filter).unwrap_or_else(|err| {
        eprintln!("gymfleet-mcp: bad log filter {filter:?} ({err}); using \"info\"");
        EnvFilter::new("info")
    });
    tracing_subscriber::fmt()
        .with_env_filter(filter)
        .with_writer(std::io::stderr)
        .with_ansi(false)
        .init();
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Clears the `GYMFLEET_*` variables, so that the caller's environment does not change
    /// the defaults these tests check (no test of this binary sets one).
    fn scrub_gymfleet_env() {
        std::env::vars_os()
            .map(|(key, _)| key)
            .filter(|key| key.to_string_lossy().starts_with("GYMFLEET_"))
            .for_each(|key| std::env::remove_var(key));
    }

    /// Every flag (and its variable) is in the README's flag table.
    #[test]
    fn the_readme_lists_every_flag() {
        use clap::CommandFactory;
        let readme = include_str!("../README.md");
        for arg in Cli::command().get_arguments() {
            let Some(long) = arg.get_long() else { continue };
            if matches!(long, "help" | "version") {
                continue;
            }
            assert!(
                readme.contains(&format!("| `--{long}")),
                "apps/mcp/README.md's flag table lacks --{long}"
            );
            if let Some(var) = arg.get_env() {
                let var = var.to_string_lossy();
                assert!(
                    readme.contains(&format!("`{var}`")),
                    "the README lacks {var}"
                );
            }
        }
    }

    #[test]
    fn servers_are_repeated_or_comma_separated() {
        scrub_gymfleet_env();
        let cli = Cli::parse_from([
            "gymfleet-mcp",
            "--server",
            "127.0.0.1:1,127.0.0.1:2",
            "--server",
            " 127.0.0.1:3 ",
        ]);
        assert_eq!(
            cli.server_addrs(),
            ["127.0.0.1:1", "127.0.0.1:2", "127.0.0.1:3"]
        );
        assert!(cli.http.is_none());
    }

    #[test]
    fn http_takes_a_socket_address() {
        scrub_gymfleet_env();
        let cli = Cli::parse_from(["gymfleet-mcp", "--http", "127.0.0.1:0"]);
        assert_eq!(cli.http, Some("127.0.0.1:0".parse().unwrap()));
        assert!(Cli::try_parse_from(["gymfleet-mcp", "--http", "nope"]).is_err());
    }
}
