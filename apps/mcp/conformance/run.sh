#!/usr/bin/env bash
# The official MCP conformance suite (@modelcontextprotocol/conformance, from npm) against
# the adapter over streamable HTTP: every server scenario that applies to a server which
# declares only tools. The suite's other scenarios drive the reference server's own test
# tools (test_simple_text, …), resources, prompts, logging or completion, which this
# adapter does not declare; undeclared methods answer "method not found" (tested in
# apps/mcp/tests/mcp/tools.rs).
#
#   cargo build -p gymfleet-mcp && bash apps/mcp/conformance/run.sh [path/to/gymfleet-mcp]
#
# Needs Node 20 and npm. Version 0.1.10 is pinned: later ones need Node 22 (fs.globSync).
set -euo pipefail
cd "$(dirname "$0")/../../.."
adapter=${1:-target/debug/gymfleet-mcp}
suite_dir=target/mcp-conformance
scenarios=(server-initialize ping tools-list server-sse-multiple-streams)

if [ ! -x "$suite_dir/node_modules/.bin/conformance" ]; then
  mkdir -p "$suite_dir"
  npm install --silent --no-audit --no-fund --prefix "$suite_dir" \
    @modelcontextprotocol/conformance@0.1.10 >/dev/null
fi

log=$(mktemp)
"$adapter" --http 127.0.0.1:0 --threads 1 2>"$log" &
pid=$!
trap 'kill "$pid" 2>/dev/null || true; rm -f "$log"' EXIT
url=""
for _ in $(seq 100); do
  url=$(grep -o 'http://127.0.0.1:[0-9]*/mcp' "$log" | head -1 || true)
  [ -n "$url" ] && break
  sleep 0.1
done
[ -n "$url" ] || { echo "the adapter did not report its address:"; cat "$log"; exit 1; }

failed=0
for scenario in "${scenarios[@]}"; do
  out=$("$suite_dir/node_modules/.bin/conformance" server --url "$url" --scenario "$scenario" 2>&1) || true
  result=$(printf '%s\n' "$out" | grep -E "^Passed: [0-9]+/[0-9]+" || true)
  echo "$scenario: ${result:-no result}"
  # Every check passed: "Passed: n/n, 0 failed, 0 warnings" with n > 0.
  if ! printf '%s\n' "$result" | grep -Eq '^Passed: ([1-9][0-9]*)/\1, 0 failed, 0 warnings$'; then
    failed=1
    printf '%s\n' "$out" | tail -20
  fi
done
exit "$failed"
