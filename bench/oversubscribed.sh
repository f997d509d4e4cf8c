#!/usr/bin/env bash
# Two threads against one on a loaded machine (issue 41, point 2), for one or more builds of
# `stripes` in the same run: each round runs every binary on run.threads = 1 and then 2,
# alternated, and prints the ratio of their stepping speeds (particle-steps/s of the
# stepping loop, `stripes run`'s summary); then the median per binary. The load:
#
#   LOAD=none     nothing added (the machine as it is)
#   LOAD=pinned   one `yes > /dev/null` pinned to the last core (`taskset`): one core busy
#   LOAD=nice     BUSY (default: the number of cores) `nice -n 10 yes` processes, unpinned
#   LOAD=busy     BUSY `yes` processes at normal priority, unpinned (BUSY=1: one core busy)
#
#   LOAD=pinned bench/oversubscribed.sh OLD NEW            # thesis scene, N = 4000
#   LOAD=nice BUSY=3 N=2000 ROUNDS=5 bench/oversubscribed.sh BIN
#   PREFIX="chrt -f 10" LOAD=none bench/oversubscribed.sh OLD NEW   # the 2/1 ratio, idle cores
#
# The busy processes are stopped at the end (also on Ctrl-C). PREFIX runs before every
# `stripes` (e.g. `chrt -f 10`, which puts the runs above every other process of the machine;
# with LOAD=pinned the busy process then gets the same priority).
set -euo pipefail
cd "$(dirname "$0")/.."
[ $# -ge 1 ] || { echo "usage: bench/oversubscribed.sh BIN [BIN...]" >&2; exit 2; }
LOAD=${LOAD:-pinned}
N=${N:-4000}
STEPS=${STEPS:-5000}
ROUNDS=${ROUNDS:-3}
BUSY=${BUSY:-$(nproc)}
PREFIX=${PREFIX:-}
work=$(mktemp -d)
busy=()
stop() { for p in "${busy[@]:-}"; do [ -n "$p" ] && kill "$p" 2> /dev/null || true; done; rm -rf "$work"; }
trap stop EXIT
last=$(($(nproc) - 1))
case "$LOAD" in
  none) ;;
  pinned) $PREFIX taskset -c "$last" yes > /dev/null & busy+=($!) ;;
  nice) for _ in $(seq "$BUSY"); do nice -n 10 yes > /dev/null & busy+=($!); done ;;
  busy) for _ in $(seq "$BUSY"); do yes > /dev/null & busy+=($!); done ;;
  *) echo "LOAD must be none, pinned, nice or busy, got $LOAD" >&2; exit 2 ;;
esac

rate() { # BIN THREADS -> particle-steps/s of the stepping loop (thesis scene, N grains)
  local bin=$1 t=$2 length
  length=$(python3 -c "print(0.4 * $N / 4000)")
  $PREFIX "$bin" run scenes/thesis-reference.toml --quiet --force --out "$work/run" \
    --set particles.count="$N" --set box.length="$length" --set prepare.duration=0 \
    --set run.duration="$(python3 -c "print($STEPS * 8e-6)")" --set run.threads="$t" \
    --set run.checkpoint_interval=0 2> /dev/null |
    tail -1 | python3 -c "import json,sys; print(json.load(sys.stdin)['particle_steps_per_s'])"
}

printf 'LOAD=%s N=%s STEPS=%s PREFIX="%s"; load before: %s\n' "$LOAD" "$N" "$STEPS" "$PREFIX" "$(uptime | sed 's/.*load/load/')"
declare -A ratios
for r in $(seq "$ROUNDS"); do
  for b in $(seq $#); do
    bin=${!b}
    one=$(rate "$bin" 1)
    two=$(rate "$bin" 2)
    q=$(python3 -c "print(f'{$two / $one:.3f}')")
    ratios[$b]="${ratios[$b]:-} $q"
    printf 'round %d %s: 1 thread %.3e, 2 threads %.3e p-steps/s, 2/1 %s\n' "$r" "$bin" "$one" "$two" "$q"
  done
done
for b in $(seq $#); do
  printf '%s: 2/1 median of %d = %s (%s)\n' "${!b}" "$ROUNDS" \
    "$(python3 -c "import statistics,sys; print(statistics.median(map(float, sys.argv[1:])))" ${ratios[$b]})" "${ratios[$b]# }"
done
printf 'load after: %s\n' "$(uptime | sed 's/.*load/load/')"
