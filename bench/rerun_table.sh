#!/usr/bin/env bash
# Reruns, at one commit and one after another, every row of BENCHMARKS.md's table ("## The
# table") that a 2-core VM can rerun in about 70 minutes. Run it on an idle machine, after
# the release build and the release wheel:
#
#   bash bench/rerun_table.sh            # from the repository root
#
# Each row's stdout and stderr go to $OUT/<ID>-<k>.log (k numbers the rows sharing an ID, in
# table order: G-1, G-2, G-3; a row with an ID of its own is <ID>-1). $OUT/index.txt gets the
# commit, the date, the machine and the package versions first, then one line per row: start
# and end (UTC), exit code (124: past its time limit), wall seconds, the estimate, the load
# average at its start. A failing row does not stop the rest.
#
# Settings (environment):
#   OUT=/tmp/rerun                 where the logs go (an existing index.txt: the old folder is
#                                  moved to $OUT.<epoch> first)
#   PY=target/pyenv/bin/python     Python of the peers (mujoco, envpool, gymnasium, dm-control…)
#   WHEEL=/tmp/wsH                 the release build of the Python package; PYTHONPATH=$WHEEL for
#                                  every Python row (subprocesses inherit it); the script stops
#                                  if `import gymfleet` does not come from there
#   SB3_PY=auto                    Python for the SB3 rows: $PY if it imports torch, else
#                                  target/rlenv/bin/python (target/pyenv has SB3 but no torch)
#   RUN_LEARN=0                    1: also G-3's learn() run (learning_parity.py, 100 000 steps,
#                                  ~4-5 min) as the last Python row: over the 70-minute budget
#   RUN_CARGO_BENCH=0              1: also the criterion rows B2, K1, H2, J1 at the end (they
#                                  compile a bench profile, -j2)
#   GS_ROUNDS=2                    GS's rounds (the row says 3; 2 keeps the total near 66 min)
#   S5_DURATION=3                  S5's seconds per side and round (the row's run used the
#                                  client's default 10; 3 is the notebook's 2026-11-28 method)
#   SETTLE=2                       seconds of sleep between rows
#   ONLY=REGEX                     run only the rows whose <ID>-<k> matches (e.g. '^(S5|N1)-')
#   FORCE_CONVERT=1                run X-1 and C-2 even if target/release/examples/convert looks stale
#   DRY_RUN=1                      check the set-up and list the rows, run none
#
# Rows NOT rerun (one line each, why):
#   H1-1 as written (builds_ab.py --before OLD): needs a build of an older commit; replaced by
#        `peer_bench.py --no-build --reacher --rounds 3 --seconds 4` (the notebook's H1 command: this
#        build vs EnvPool Reacher-v5 on the same reacher.xml, 64/256 envs, 2 and 5 substeps, ctrl in [-1, 1])
#   L4-2 embedded_loop.py "the two wheels alternated": compares two builds (6223bb8 vs the commit after)
#   S-1  embedded_loop.py, two wheels alternated four times: compares two builds (f2c0fbc -> f8370a3)
#   L3-1 learning run: PPO, 3 ids x 3 seeds x 300 000 steps per side, sized for a 16-core machine
#   C-3  learning run: PPO transfer, 3 seeds x 300 000 steps per side, then --cross (hours here)
#   D-3  learning run: SAC, 2 seeds x 100 000 steps per side (hours on 2 cores)
#   A-2  learning run: CleanRL PPO, 2 x 8 seeds x 100 000 steps (hours)
#   F-1  compares two builds (112478c vs the next) under callgrind
#   O1-1 the contact-work limit on vs off under callgrind: a build/setting A/B (not rerun, as F),
#        and it needs target/release/examples/convert
#   M3-1 wire_ab.py --before OLD: needs a build of 0d17d9b
#   M4-1 wrapper_share.py with two wheels (0d4d947^ vs c7aa9be): compares two builds
#   O2-1 first build from nothing (CPU-minutes of cargo and pip): a build, not a benchmark
#   G-3's learn() part (learning_parity.py --steps 100000): ~4-5 min, does not fit; RUN_LEARN=1
#   B2-1, K1-1, H2-1, J1-1 (criterion): only with RUN_CARGO_BENCH=1, at the end
#   Z1b-1 is not run on its own: S1-1's command (rollout_ceiling.py, all ten files) covers it;
#        its log is copied to Z1b-1.log
# Run only if a fresh convert example exists (target/release/examples/convert is not part of
# the release build this script expects; `cargo build --release -j2 -p gymfleet-import
# --example convert` makes it): X-1 (loops_bench.py) and C-2 (suite_builds.py --before-rigid
# --callgrind). "Fresh": no file of crates/import, crates/assembly, vendor/parry3d,
# vendor/mesh-loader or Cargo.lock newer than the binary; else SKIPPED in index.txt.
#
# Changed from the Reproduce column: /tmp/peer/bin/python and `python` are $PY; `cargo run
# --release --example E -- ARGS` is target/release/examples/E ARGS; peer_bench.py gets
# --no-build (it runs cargo build otherwise; no other script calls cargo); P1 also writes
# --json $OUT/P1-1.json; S6 converts half_cheetah.xml with gymfleet.convert (the same
# gymfleet_import conversion as the convert example) into $OUT/hc.json and runs N = 1, 256,
# 1024, prefetch off and on, two rounds; S5 runs its six cells in one log with
# --duration $S5_DURATION --warmup 1; GS runs $GS_ROUNDS rounds; learning_parity.py writes
# under $OUT/learning_parity (its default folder resumes old runs); N1 drops --renice when not
# root; C-1 adds gait_probe.py Hopper 64 and Walker2d 64 (figures its row gives); O2-2 runs
# reference.json's 13 runs. G-1 and B3 keep --json bench/results/{suite,scaling}.json; G-1's
# file is set aside while B3 runs and put back after it, so that B3's provenance() does not
# record the commit as "-dirty" because of G-1's file.

set -u
cd "$(dirname "$0")/.." || exit 2
ROOT=$PWD

abs() { case $1 in /*) printf '%s' "$1" ;; */*) printf '%s/%s' "$ROOT" "$1" ;; *) printf '%s' "$1" ;; esac; }
OUT=$(abs "${OUT:-/tmp/rerun}")
PY=$(abs "${PY:-$ROOT/target/pyenv/bin/python}")
WHEEL=$(abs "${WHEEL:-/tmp/wsH}")
SB3_PY=${SB3_PY:-auto}
RUN_LEARN=${RUN_LEARN:-0}
RUN_CARGO_BENCH=${RUN_CARGO_BENCH:-0}
GS_ROUNDS=${GS_ROUNDS:-2}
S5_DURATION=${S5_DURATION:-3}
SETTLE=${SETTLE:-2}
ONLY=${ONLY:-}
FORCE_CONVERT=${FORCE_CONVERT:-0}
DRY_RUN=${DRY_RUN:-0}
REL=$ROOT/target/release
CONVERT=$REL/examples/convert

if [ -e "$OUT/index.txt" ]; then
  mv "$OUT" "$OUT.$(date +%s)" || exit 2
fi
mkdir -p "$OUT" || exit 2
INDEX=$OUT/index.txt
: >"$INDEX"
say() { printf '%s\n' "$*" | tee -a "$INDEX"; }

if [ ! -d "$WHEEL" ] && [ "$DRY_RUN" != 1 ]; then
  say "FATAL: WHEEL=$WHEEL is not a folder (the release build of the Python package)"
  exit 2
fi
export PYTHONPATH=$WHEEL
if [ "$SB3_PY" = auto ]; then
  if "$PY" -c 'import torch' >/dev/null 2>&1; then SB3_PY=$PY; else SB3_PY=$ROOT/target/rlenv/bin/python; fi
fi
SB3_PY=$(abs "$SB3_PY")
export OUT PY WHEEL SB3_PY GS_ROUNDS S5_DURATION ROOT REL CONVERT

# --- what, where, with which versions ---------------------------------------------------
say "# bench/rerun_table.sh"
say "commit: $(git rev-parse HEAD)"
say "date: $(date -u)"
say "git status (tracked): $(git status --porcelain --untracked-files=no | tr '\n' ' ')"
say "machine: $(uname -srm), $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2-)"
say "load average at start: $(cut -d' ' -f1-3 /proc/loadavg)"
say "OUT=$OUT PY=$PY WHEEL=$WHEEL SB3_PY=$SB3_PY PYTHONPATH=$PYTHONPATH"
say "RUN_LEARN=$RUN_LEARN RUN_CARGO_BENCH=$RUN_CARGO_BENCH GS_ROUNDS=$GS_ROUNDS S5_DURATION=$S5_DURATION ONLY=$ONLY"
versions() {  # $1: python; prints the packages' versions and where gymfleet comes from
  "$1" - "$WHEEL" <<'EOF'
import importlib.metadata as md, os, sys
names = ["gymfleet", "mujoco", "envpool", "gymnasium", "dm-control", "gymnasium-robotics",
         "stable-baselines3", "torch", "numpy", "scipy", "matplotlib"]
def version(n):
    try:
        return md.version(n)
    except md.PackageNotFoundError:
        return "-"
print(f"python {sys.version.split()[0]} ({sys.executable}): " + ", ".join(f"{n} {version(n)}" for n in names))
import gymfleet
where = os.path.realpath(gymfleet.__file__)
print(f"gymfleet {getattr(gymfleet, '__version__', '?')} imported from {where}")
sys.exit(0 if where.startswith(os.path.realpath(sys.argv[1]) + os.sep) else 3)
EOF
}
for py in "$PY" "$SB3_PY"; do
  v=$(versions "$py" 2>&1); rc=$?
  say "$v"
  if [ "$rc" -ne 0 ] && [ "$py" = "$PY" ] && [ "$DRY_RUN" != 1 ]; then
    say "FATAL: $PY does not import gymfleet from $WHEEL (rc $rc)"
    exit 3
  elif [ "$rc" -ne 0 ]; then
    say "WARNING: $py does not import gymfleet from $WHEEL (rc $rc)$([ "$py" = "$SB3_PY" ] && echo ': G-3 will fail or measure another build')"
  fi
  [ "$SB3_PY" = "$PY" ] && break
done
head_time=$(git log -1 --format=%ct)
for b in gymfleet-load gymfleet-server examples/peer_step examples/task_cost examples/fairness \
         examples/checkpoint_cost examples/convert; do
  if [ -x "$REL/$b" ]; then
    t=$(stat -c %Y "$REL/$b")
    note=""; [ "$t" -lt "$head_time" ] && note="  (WARNING: older than HEAD's commit)"
    say "binary $b: $(date -u -d "@$t" +%FT%TZ)$note"
  else
    say "binary $b: MISSING"
  fi
done
convert_fresh() {
  [ -x "$CONVERT" ] || return 1
  [ "$FORCE_CONVERT" = 1 ] && return 0
  [ -z "$(find crates/import crates/assembly vendor/parry3d vendor/mesh-loader Cargo.lock \
          -newer "$CONVERT" -type f -print -quit 2>/dev/null)" ]
}

# --- the rows ---------------------------------------------------------------------------
# Each row is a function; run_row runs it in a fresh bash under `timeout` (3x its estimate +
# 2 min), its output to $OUT/<ID>-<k>.log.
r_P1_1() { "$PY" bench/peer/peer_bench.py --no-build --rounds 9 --steps 2000 --repeats 3 --json "$OUT/P1-1.json"; }
r_P2_1() { "$PY" bench/peer/peer_bench.py --no-build --throughput --rounds 5 --seconds 5; }
r_H1_1() { "$PY" bench/peer/peer_bench.py --no-build --reacher --rounds 3 --seconds 4; }
r_H1_2() { "$PY" bench/peer/reacher_accuracy.py; }
r_H3_1() { "$PY" bench/peer/peer_bench.py --no-build --locomotion --reacher-envs 64 256 --rounds 3 --seconds 4; }
r_F1_1() { "$PY" bench/python/python_bench.py --rounds 5 --duration 5 --warmup 1; }
r_GS_1() { "$PY" bench/python/suite_bench.py --envs 64 256 --rounds "$GS_ROUNDS" --seconds 2; }
r_G_1() { "$PY" bench/python/suite_bench.py --envs 64 256 --rounds 3 --seconds 2 --no-sync --json bench/results/suite.json; }
r_B3_1() { "$PY" bench/python/scaling.py --names Hopper HalfCheetah --json bench/results/scaling.json; }
r_G_2() { "$PY" bench/python/single_env.py --rounds 3 --steps 2000; }
r_G_3() { "$SB3_PY" bench/python/sb3_step.py --name Hopper --steps 5000 --rounds 3; }
r_S1_1() { "$PY" bench/peer/rollout_ceiling.py --rounds 3; }   # all ten files: S1-1's six and Z1b's four
r_S1_2() { cd bench/peer && "$PY" contact_scaling.py --rounds 3; }
r_S4_1() { "$PY" bench/python/substep_fidelity.py; }
r_S6_1() {
  "$PY" -c 'import json, sys, gymfleet
doc, warnings = gymfleet.convert("crates/import/tests/data/half_cheetah.xml")
json.dump(doc, open(sys.argv[1], "w"))
print("hc.json written;", len(warnings), "conversion warnings:", *warnings, sep="\n  ")' "$OUT/hc.json" || return $?
  local rc=0 round n pf
  for round in 1 2; do for n in 1 256 1024; do for pf in off on; do
    echo "## round $round, --envs $n, --prefetch $pf"
    "$REL/examples/peer_step" --document "$OUT/hc.json" --end-effector torso --substeps 5 --dt 0.05 \
      --variant random --amplitudes 120,90,60,120,60,30 --steps 200 --repeats 3 --envs "$n" --prefetch "$pf" || rc=$?
  done; done; done
  return $rc
}
r_X_1() { "$PY" bench/peer/loops_bench.py --rounds 3; }
r_L4_1() { bash bench/latency.sh 5; }
r_S5_1() {
  local rc=0 mode n
  for mode in unary stream; do for n in 16 256 1024; do
    echo "## --mode $mode --n-envs $n"
    "$REL/gymfleet-load" --compare --rounds 3 --model arm2 --n-envs "$n" --mode "$mode" --window 2 --threads 2 \
      --duration "$S5_DURATION" --warmup 1 || rc=$?
  done; done
  return $rc
}
r_L5_1() { "$REL/gymfleet-load" --model arm2 --n-envs 10000 --steps 10 --threads 2 --report-rss; }
r_I1_1() { "$REL/examples/fairness" 2 10 16384 10; }
r_N1_1() {
  if [ "$(id -u)" = 0 ]; then
    "$PY" bench/python/neighbour_bench.py --rounds 3 --seconds 3 --renice 10
  else
    echo "## not root: --renice 10 left out (it needs CAP_SYS_NICE)"
    "$PY" bench/python/neighbour_bench.py --rounds 3 --seconds 3
  fi
}
r_G1_1() {
  local rc=0
  echo "## ars_reach.py"; "$PY" client/python/examples/ars_reach.py || rc=$?
  echo "## ars_cartpole.py"; "$PY" client/python/examples/ars_cartpole.py || rc=$?
  return $rc
}
r_G2_1() { "$REL/examples/task_cost" 150; }
r_C_1() {
  local rc=0 name
  echo "## contact_softness_probe.py --episodes 20"
  "$PY" bench/python/contact_softness_probe.py --episodes 20 || rc=$?
  for name in HalfCheetah Hopper Walker2d; do
    echo "## gait_probe.py $name 64"; "$PY" bench/python/gait_probe.py "$name" 64 || rc=$?
  done
  return $rc
}
r_C_2() {
  "$PY" bench/peer/suite_builds.py "$REL/examples/peer_step" "$REL/examples/peer_step" --before-rigid \
    --models half_cheetah ant hopper walker2d humanoid --callgrind --rounds 1
}
r_D_1() { "$PY" bench/python/dmc_bench.py --envs 64 --rounds 2 --seconds 1.5; }
r_D_2() { "$PY" bench/python/dmc_bench.py --tasks ManipulatorBringBall CheetahRun --envs 64 --rounds 3 --seconds 2; }
r_A_1() { "$PY" bench/python/async_bench.py --rounds 3 --seconds 3; }
r_J2_1() { "$REL/examples/checkpoint_cost" 256 100 1000 5; }
r_O2_2() {
  local rc=0 m t place
  mkdir -p "$OUT/O2-2"
  for m in arm2 arm6 chain20; do for t in 1 2; do for place in in_process embedded; do
    echo "## $place, $m, 256 envs, $t thread(s)"
    "$REL/gymfleet-load" --model "$m" --n-envs 256 --threads "$t" $([ "$place" = in_process ] && echo --in-process) \
      --duration 4 --warmup 1 --json "$OUT/O2-2/$place-$m-$t.json" || rc=$?
  done; done; done
  echo "## embedded, pendulum, one env (--api env), 1 thread"
  "$REL/gymfleet-load" --model pendulum --api env --threads 1 --duration 4 --warmup 1 \
    --json "$OUT/O2-2/embedded-pendulum-env-1.json" || rc=$?
  return $rc
}
r_G_3_learn() { "$SB3_PY" bench/python/learning_parity.py --names Hopper --seeds 0 --steps 100000 --out "$OUT/learning_parity"; }
r_B2_1() { cargo bench -j2 -p gymfleet-batch --bench batch_step -- --warm-up-time 1 --measurement-time 3 batch_step; }
r_K1_1() { cargo bench -j2 -p gymfleet-render --bench render -- --warm-up-time 1 --measurement-time 3; }
r_H2_1() { cargo bench -j2 -p gymfleet-import --bench convert -- --warm-up-time 1 --measurement-time 3; }
r_J1_1() { cargo bench -j2 -p gymfleet-env --bench state -- --warm-up-time 1 --measurement-time 2; }

TOTAL_EST=0
ROW_PID=
# Ctrl-C or a TERM: the row runs in a process group of its own (timeout's), so pass it on.
trap '[ -n "$ROW_PID" ] && kill -TERM "$ROW_PID" 2>/dev/null; say "# interrupted $(date -u +%FT%TZ)"; exit 130' INT TERM
run_row() {  # run_row NAME ESTIMATE_S FUNCTION: NAME is <ID>-<k>, the log $OUT/NAME.log (appended)
  local name=$1 est=$2 fn=$3 log=$OUT/$1.log start t0 load0 rc wall ok
  if [ -n "$ONLY" ] && ! [[ $name =~ $ONLY ]]; then return 0; fi
  TOTAL_EST=$((TOTAL_EST + est))
  start=$(date -u +%FT%TZ); t0=$(date +%s); load0=$(cut -d' ' -f1-3 /proc/loadavg)
  printf '%-8s start %s  load %s  est %5d s  ...\n' "$name" "$start" "$load0" "$est"
  {
    echo "# $name ($fn), started $start, commit $(git rev-parse --short HEAD)"
    declare -f "$fn" | sed 's/^/#   /'
  } >>"$log"
  if [ "$DRY_RUN" = 1 ]; then
    bash -n -c "$(declare -f "$fn")" 2>>"$log" && ok=parses || ok="DOES NOT PARSE"
    printf '%-8s dry run: %s %s\n' "$name" "$fn" "$ok" | tee -a "$INDEX"
    return 0
  fi
  timeout -k 30 $((3 * est + 120)) bash -c "$(declare -f "$fn")
cd \"\$ROOT\" || exit 2
$fn" </dev/null >>"$log" 2>&1 &
  ROW_PID=$!
  wait "$ROW_PID"
  rc=$?
  ROW_PID=
  wall=$(( $(date +%s) - t0 ))
  printf '# %s: exit %d after %d s\n' "$name" "$rc" "$wall" >>"$log"
  printf '%-8s start %s  end %s  rc %3d%s  wall %5d s  est %5d s  load %s\n' "$name" "$start" \
    "$(date -u +%FT%TZ)" "$rc" "$([ "$rc" = 124 ] || [ "$rc" = 137 ] && echo ' TIMEOUT')" "$wall" "$est" \
    "$load0" | tee -a "$INDEX"
  sleep "$SETTLE"
}
skip_row() {  # skip_row NAME REASON
  if [ -n "$ONLY" ] && ! [[ $1 =~ $ONLY ]]; then return 0; fi
  printf '%-8s SKIPPED  %s\n' "$1" "$2" | tee -a "$INDEX"
}

say "# rows: name, start, end (UTC), exit code, wall s, estimate s, load average"
run_row P1-1   60 r_P1_1
run_row P2-1   60 r_P2_1
run_row H1-1  115 r_H1_1      # in place of builds_ab.py --before OLD (see the top)
run_row H1-2   10 r_H1_2
run_row H3-1  140 r_H3_1
run_row F1-1   95 r_F1_1
run_row GS-1  360 r_GS_1
suite_clean=0
git diff --quiet -- bench/results/suite.json && suite_clean=1
run_row G-1   320 r_G_1
aside=0
if [ "$suite_clean" = 1 ] && ! git diff --quiet -- bench/results/suite.json; then
  cp bench/results/suite.json "$OUT/suite.json" && git checkout -q -- bench/results/suite.json && aside=1
fi
run_row B3-1  320 r_B3_1
if [ "$aside" = 1 ]; then cp "$OUT/suite.json" bench/results/suite.json; fi
run_row G-2    60 r_G_2
run_row G-3    25 r_G_3       # sb3_step.py; the learn() part: RUN_LEARN=1, after the last row below
run_row S1-1  200 r_S1_1
if [ -e "$OUT/S1-1.log" ]; then
  cp "$OUT/S1-1.log" "$OUT/Z1b-1.log"
  printf '%-8s = S1-1 (the same rollout_ceiling.py --rounds 3 run, all ten files; log copied)\n' Z1b-1 | tee -a "$INDEX"
fi
run_row S1-2  100 r_S1_2
run_row S4-1   15 r_S4_1
run_row S6-1  110 r_S6_1
if convert_fresh; then run_row X-1 15 r_X_1
else skip_row X-1 "target/release/examples/convert missing or older than crates/import & co (FORCE_CONVERT=1 to run anyway)"; fi
run_row L4-1  165 r_L4_1
run_row S5-1  175 r_S5_1
run_row L5-1   15 r_L5_1
run_row I1-1   30 r_I1_1
run_row N1-1  640 r_N1_1
run_row G1-1   50 r_G1_1
run_row G2-1   12 r_G2_1
run_row C-1    30 r_C_1
if convert_fresh && command -v valgrind >/dev/null; then run_row C-2 120 r_C_2
else skip_row C-2 "needs valgrind and a fresh target/release/examples/convert (FORCE_CONVERT=1 to run anyway)"; fi
run_row D-1   380 r_D_1
run_row D-2    55 r_D_2
run_row A-1   145 r_A_1
run_row J2-1   20 r_J2_1
run_row O2-2   75 r_O2_2
if [ "$RUN_LEARN" = 1 ]; then run_row G-3 300 r_G_3_learn; fi
if [ "$RUN_CARGO_BENCH" = 1 ]; then
  run_row B2-1 300 r_B2_1
  run_row K1-1 300 r_K1_1
  run_row H2-1 300 r_H2_1
  run_row J1-1 300 r_J1_1
fi
say "# done $(date -u +%FT%TZ); estimates of the rows run: $TOTAL_EST s ($((TOTAL_EST / 60)) min)"
