#!/usr/bin/env bash
# Threads against rate on a many-core host (issue 41, point 1): particle-steps per second of
# the stepping loop (`stripes run`'s summary) on run.threads = 1, 2, 4, 8, 16 (THREADS), for
# the thesis scene at N = 4000, 16000 and 64000 (box.length scaled with N, from the lattice at
# dt = 8e-6 s), the stripe scene at 0.4 m (N = 8000, dt = "auto") and the experiment's tray
# (N = 4848, end walls, its fluidising stage, dt = "auto"), printed side by side
# with the speed-up over one thread. Made to run in under 5 minutes on a 16-core host with
# ROUNDS=1 (each row's runs are a few seconds each there).
#
# On the machine that builds (a stripped release binary and the scenes, in one file):
#   bench/scaling.sh pack /tmp/scaling.tar.gz
# On the many-core host:
#   mkdir s && tar -xzf scaling.tar.gz -C s && cd s && bench/scaling.sh run
#   THREADS="1 2 4 8 16 32" ROUNDS=3 bench/scaling.sh run   # median of 3 per cell
# `bench/scaling.sh run` in a checkout uses target/release/stripes (BIN=... for another).
set -euo pipefail
# Every step on the threads asked for: a run's pace (particles/src/pace.rs) would otherwise
# step on fewer threads where fewer are faster, and the table would not show the team's rate.
export STRIPES_FIXED_TEAM=1
cd "$(dirname "$0")/.."
mode=${1:-run}
if [ "$mode" = pack ]; then
  out=${2:?usage: bench/scaling.sh pack OUT.tar.gz}
  cargo build --release --bin stripes
  stage=$(mktemp -d)
  mkdir -p "$stage/bench" "$stage/scenes" "$stage/target/release"
  cp bench/scaling.sh "$stage/bench/"
  cp scenes/thesis-reference.toml scenes/stripes.toml scenes/experiment.toml "$stage/scenes/"
  strip -o "$stage/target/release/stripes" target/release/stripes
  tar -czf "$out" -C "$stage" .
  rm -rf "$stage"
  echo "packed $out ($(du -h "$out" | cut -f1))"
  exit 0
fi
[ "$mode" = run ] || { echo "usage: bench/scaling.sh run | pack OUT.tar.gz" >&2; exit 2; }
BIN=${BIN:-target/release/stripes}
THREADS=${THREADS:-"1 2 4 8 16"}
ROUNDS=${ROUNDS:-1}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# rate SCENE_FILE STEPS DT THREADS [--set ...] -> particle-steps/s of the stepping loop
rate() {
  local file=$1 steps=$2 dt=$3 t=$4
  shift 4
  if [ "$dt" = auto ]; then
    dt=$("$BIN" run "$file" --quiet --out "$work/dt" --force --set prepare.duration=0 --set run.duration=1e-9 \
      --set run.checkpoint_interval=0 "$@" 2> /dev/null | tail -1 | python3 -c "import json,sys; print(json.load(sys.stdin)['dt'])")
  fi
  "$BIN" run "$file" --quiet --force --out "$work/run" --set prepare.duration=0 \
    --set run.duration="$(python3 -c "print($steps * $dt)")" --set run.threads="$t" \
    --set run.checkpoint_interval=0 "$@" 2> /dev/null |
    tail -1 | python3 -c "import json,sys; print(json.load(sys.stdin)['particle_steps_per_s'])"
}

# name | scene | steps | dt | sets
rows=(
  "thesis N=4000|scenes/thesis-reference.toml|4000|8e-6|--set particles.count=4000 --set box.length=0.4"
  "thesis N=16000|scenes/thesis-reference.toml|1500|8e-6|--set particles.count=16000 --set box.length=1.6"
  "thesis N=64000|scenes/thesis-reference.toml|400|8e-6|--set particles.count=64000 --set box.length=6.4"
  "stripes 0.4 m N=8000|scenes/stripes.toml|1500|auto|--set particles.count=8000 --set box.length=0.4"
  "experiment N=4848|scenes/experiment.toml|1500|auto|"
)
echo "host: $(nproc) cores, $(uname -m); $(grep -m1 'model name' /proc/cpuinfo 2> /dev/null | cut -d: -f2 | sed 's/^ //')"
echo "load before: $(uptime | sed 's/.*load/load/')"
header="scene"
for t in $THREADS; do header="$header | $t"; done
echo "particle-steps/s (median of $ROUNDS), speed-up over the first column in brackets"
echo "| $header |"
echo "|---$(for _ in $THREADS; do printf '|---'; done)|"
for row in "${rows[@]}"; do
  IFS='|' read -r name file steps dt sets <<< "$row"
  line="$name"
  base=""
  for t in $THREADS; do
    vals=()
    for _ in $(seq "$ROUNDS"); do
      # shellcheck disable=SC2086
      vals+=("$(rate "$file" "$steps" "$dt" "$t" $sets)")
    done
    v=$(python3 -c "import statistics,sys; print(statistics.median(map(float, sys.argv[1:])))" "${vals[@]}")
    [ -n "$base" ] || base=$v
    line="$line | $(python3 -c "print(f'{$v:.3g} ({$v / $base:.2f}x)')")"
  done
  echo "| $line |"
done
echo "load after: $(uptime | sed 's/.*load/load/')"
