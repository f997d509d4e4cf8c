#!/usr/bin/env bash
# bench/speed-ratio.sh's comparison in on-CPU time: user CPU seconds of whole one-thread
# `stripes run`s (set-up included, small), which a busy shared machine disturbs far less
# than wall time. Prints per round the user seconds of OLD and NEW and old / new, then the
# median ratio, for the thesis scene (N = 4000) and the stripe scene (N = 2000), both from
# the lattice, STEPS steps each.
#
#   bench/speed-ratio-cpu.sh OLD NEW
#   STEPS=40000 ROUNDS=5 bench/speed-ratio-cpu.sh OLD NEW
set -euo pipefail
cd "$(dirname "$0")/.."
source bench/lib.sh
OLD=$1
NEW=$2
STEPS=${STEPS:-20000}
ROUNDS=${ROUNDS:-3}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
user() { # BIN SCENE DT -> user seconds
  local out="$work/run"
  rm -rf "$out"
  /usr/bin/time -f "%U" -o "$work/time" "$1" run "$2" --quiet --out "$out" --set prepare.duration=0 \
    --set run.duration="$(python3 -c "print($STEPS * $3)")" --set run.threads=1 \
    --set run.checkpoint_interval=0 > /dev/null 2>&1
  tail -1 "$work/time"
}
# The stripe scene's dt = "auto", read from a one-step run.
stripes_dt=$(auto_dt "$NEW" scenes/stripes.toml "$work/dt")
for scene in "thesis scenes/thesis-reference.toml 8e-6" "stripes scenes/stripes.toml $stripes_dt"; do
  set -- $scene
  printf '%s, %s steps, load before: %s\n' "$1" "$STEPS" "$(uptime | sed 's/.*load/load/')"
  ratios=""
  for R in $(seq 1 "$ROUNDS"); do
    a=$(user "$OLD" "$2" "$3")
    b=$(user "$NEW" "$2" "$3")
    r=$(python3 -c "print($a / $b)")
    printf '  round %d: old %s s, new %s s, old / new %.3f\n' "$R" "$a" "$b" "$r"
    ratios="$ratios $r"
  done
  python3 -c "import statistics,sys; print('  median %.3f' % statistics.median(map(float, sys.argv[1:])))" $ratios
done
printf 'load after: %s\n' "$(uptime | sed 's/.*load/load/')"
