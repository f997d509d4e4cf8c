#!/usr/bin/env bash
# The default thread count under load (issue 20, point 1): starts one busy process per core
# (`yes > /dev/null`), runs the same short tray with run.threads = 1 and with the default
# run.threads = 0 (which chooses, src/host/threads.rs), alternating, and prints the ratio of their
# stepping speeds; the busy processes are stopped afterwards (also on Ctrl-C). The goal: the
# default at most 1.3x slower than one thread, at 200 grains and at 4000.
#
#   bench/under-load.sh                  # N = 200 and 4000, 3 rounds
#   SIZES="200" ROUNDS=5 bench/under-load.sh
set -euo pipefail
cd "$(dirname "$0")/.."
SIZES=${SIZES:-"200 4000"}
ROUNDS=${ROUNDS:-3}
STEPS=${STEPS:-4000}
cargo build --release -q
bin=target/release/stripes
work=$(mktemp -d)
busy=()
stop() { for p in "${busy[@]:-}"; do [ -n "$p" ] && kill "$p" 2> /dev/null || true; done; rm -rf "$work"; }
trap stop EXIT
for _ in $(seq "$(nproc)"); do yes > /dev/null & busy+=($!); done
echo "$(nproc) busy processes started: ${busy[*]}" >&2

speed() { # N THREADS -> particle-steps/s of the stepping loop
  local n=$1 t=$2 length dt duration
  length=$(python3 -c "print(0.4 * $n / 4000)")
  dt=8e-6
  duration=$(python3 -c "print($STEPS * $dt)")
  "$bin" run scenes/thesis-reference.toml --quiet --force --out "$work/run" --sample-cache "$work/samples" \
    --set particles.count="$n" --set box.length="$length" --set prepare.duration=0 \
    --set run.duration="$duration" --set run.threads="$t" --set run.checkpoint_interval=0 2> /dev/null |
    tail -1 | python3 -c "import json,sys; s=json.loads(sys.stdin.read()); print(s['particle_steps_per_s'], s['threads'])"
}

printf '%6s %5s %14s %14s %8s %7s\n' N round one_thread default default_threads ratio
results=()
for n in $SIZES; do
  ratios=()
  for r in $(seq "$ROUNDS"); do
    read -r one _ < <(speed "$n" 1)
    read -r def threads < <(speed "$n" 0)
    ratio=$(python3 -c "print(f'{$one / $def:.3f}')")
    ratios+=("$ratio")
    printf '%6s %5s %14.3e %14.3e %8s %7s\n' "$n" "$r" "$one" "$def" "$threads" "$ratio"
  done
  median=$(printf '%s\n' "${ratios[@]}" | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}')
  echo "N = $n: one thread / default, median of $ROUNDS = $median (goal <= 1.3)"
  results+=("\"$n\": $median")
done
echo "{\"under_load_slowdown_of_default\": {$(IFS=,; echo "${results[*]}")}}"
