#!/usr/bin/env bash
# Where a single-env Step's latency goes (BENCHMARKS.md, L4): a gymfleet-server process
# on TCP loopback and one on a Unix-domain socket, each driven by the load client with
# --api ping (GetServerInfo: the transport), --api observe (the pool hand-off, no physics)
# and --api env (Step: plus the physics), one call at a time on the seed pendulum.
# Rounds alternate the transports; the table gives the median over rounds of each run's
# p50 / p90 / p99 in µs.
#
#   cargo build --release -p gymfleet-server -p gymfleet-load
#   bash bench/latency.sh [rounds] [seconds per run]
set -euo pipefail
cd "$(dirname "$0")/.."
rounds=${1:-5}
seconds=${2:-4}
server=target/release/gymfleet-server
load=target/release/gymfleet-load
out=$(mktemp -d)
sock="$out/gymfleet.sock"
trap 'kill "${pid:-}" 2>/dev/null || true; rm -rf "$out"' EXIT

for round in $(seq "$rounds"); do
  for transport in tcp uds; do
    if [ "$transport" = tcp ]; then addr=127.0.0.1:50099; else addr="unix:$sock"; fi
    "$server" --threads 2 --listen "$addr" 2>/dev/null &
    pid=$!
    for _ in $(seq 50); do "$load" --server "$addr" --api ping --steps 1 --quiet >/dev/null 2>&1 && break; sleep 0.1; done
    for api in ping observe env; do
      "$load" --server "$addr" --api "$api" --model pendulum --duration "$seconds" --warmup 1 \
        --quiet --json "$out/$round-$transport-$api.json" >/dev/null
    done
    kill "$pid"; wait "$pid" 2>/dev/null || true
  done
done

python3 - "$out" <<'EOF'
import glob, json, os, statistics, sys
runs = {}
for path in glob.glob(os.path.join(sys.argv[1], "*.json")):
    _, transport, api = os.path.basename(path)[:-5].split("-")
    lat = json.load(open(path))["runs"][0]["latency_us"]
    runs.setdefault((transport, api), []).append(lat)
print(f"{'transport':9} {'call':8} {'p50':>6} {'p90':>6} {'p99':>6}  (µs, median over {len(runs[('tcp', 'ping')])} rounds)")
for transport in ("tcp", "uds"):
    for api, name in (("ping", "ping"), ("observe", "observe"), ("env", "step")):
        lats = runs[(transport, api)]
        med = {q: statistics.median(l[q] for l in lats) for q in ("p50", "p90", "p99")}
        print(f"{transport:9} {name:8} {med['p50']:6.0f} {med['p90']:6.0f} {med['p99']:6.0f}")
EOF
