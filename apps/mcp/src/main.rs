//! `gymfleet-mcp`: the MCP adapter's command (see the library, `src/lib.rs`).

fn main() -> std::process::ExitCode {
    gymfleet_mcp::main()
}
