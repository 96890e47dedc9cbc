"""A/B of the step hot path: the load client at 0d17d9b (before M3's wire changes) and at
HEAD, alternated round by round, each with its embedded server (loopback gRPC)."""
import json, subprocess, statistics, sys
BIN = {"before": "/tmp/before/target/release/gymfleet-load", "after": "/work/main/target/release/gymfleet-load"}
WORK = {
    "env pendulum": ["--api", "env", "--model", "pendulum"],
    "batch arm2 x64": ["--api", "batch", "--model", "arm2", "--n-envs", "64"],
}
ROUNDS = int(sys.argv[1]) if len(sys.argv) > 1 else 3
res = {(w, s): [] for w in WORK for s in BIN}
for r in range(ROUNDS):
    for w, args in WORK.items():
        order = ["before", "after"] if r % 2 == 0 else ["after", "before"]
        for side in order:
            subprocess.run([BIN[side], *args, "--duration", "3", "--warmup", "1", "--threads", "1", "--json", "/tmp/ab.json"],
                           check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            run = json.load(open("/tmp/ab.json"))["runs"][0]
            res[(w, side)].append((run["env_steps_per_s"], run["latency_us"]["p50"]))
for w in WORK:
    b = [x for x, _ in res[(w, "before")]]; a = [x for x, _ in res[(w, "after")]]
    bl = [p for _, p in res[(w, "before")]]; al = [p for _, p in res[(w, "after")]]
    print(f"| {w} | {', '.join(f'{x:,.0f}' for x in b)} | {', '.join(f'{x:,.0f}' for x in a)} | "
          f"{statistics.median(a)/statistics.median(b):.3f} | {statistics.median(bl)} / {statistics.median(al)} µs |")
