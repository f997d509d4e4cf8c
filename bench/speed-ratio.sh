#!/usr/bin/env bash
# Speed of two builds of `stripes` against each other, in one run: particle-steps per second
# of the stepping loop (`stripes run`'s summary), the two binaries alternated round by round
# so that both see the same spell of a shared machine; prints each round and the median of
# the rounds' ratios new / old.
#
#   bench/speed-ratio.sh OLD NEW                      # thesis scene, N = 4000, 1 thread
#   SCENE=stripes bench/speed-ratio.sh OLD NEW        # the stripe scene (N = 2000)
#   THREADS=2 ROUNDS=5 bench/speed-ratio.sh OLD NEW
#   STATE=gas bench/speed-ratio.sh OLD NEW            # thesis scene from its gas (see vs-lammps.sh)
#   bench/speed-ratio.sh BIN BIN                      # THREADS="1 2": 2-thread / 1-thread scaling
#
# SCENE=thesis (default): scenes/thesis-reference.toml from the lattice (prepare.duration = 0),
# STEPS steps at dt = 8e-6 s. SCENE=stripes: scenes/stripes.toml from the lattice, STEPS steps
# at its dt = "auto". With THREADS="1 2" and OLD = NEW it compares thread counts instead.
set -euo pipefail
# Every step on the threads asked for: a run's pace (particles/src/pace.rs) would otherwise
# step on fewer threads where fewer are faster, and the table would not show the team's rate.
export STRIPES_FIXED_TEAM=1
cd "$(dirname "$0")/.."
source bench/lib.sh
OLD=$1
NEW=$2
SCENE=${SCENE:-thesis}
STATE=${STATE:-lattice}
STEPS=${STEPS:-5000}
ROUNDS=${ROUNDS:-3}
THREADS=${THREADS:-1}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

case "$SCENE" in
  thesis) file=scenes/thesis-reference.toml; dt=8e-6 ;;
  stripes) file=scenes/stripes.toml; dt=auto ;;
  *) echo "SCENE must be thesis or stripes, got $SCENE" >&2; exit 2 ;;
esac

# One run of binary $1 on $2 threads: prints its particle-steps per second.
rate() {
  local bin=$1 threads=$2 dir="$work/run"
  rm -rf "$dir"
  if [ "$STATE" = gas ]; then
    cp -a out/bench-gas "$dir"
    "$bin" run "$dir/scene.toml" --resume --quiet --out "$dir" \
      --set run.duration="$(python3 -c "print(10 + $STEPS * 8e-6)")" --set run.threads="$threads" \
      --set run.checkpoint_interval=0 2> /dev/null | tail -1
  else
    # Simulated time for STEPS steps: the scene's dt ("auto": read from a 1-step run).
    local step=$dt
    if [ "$dt" = auto ]; then
      step=$(auto_dt "$bin" "$file" "$dir")
    fi
    "$bin" run "$file" --quiet --out "$dir" --set prepare.duration=0 \
      --set run.duration="$(python3 -c "print($STEPS * $step)")" --set run.threads="$threads" \
      --set run.checkpoint_interval=0 2> /dev/null | tail -1
  fi | python3 -c "import json,sys; print(json.load(sys.stdin)['particle_steps_per_s'])"
}

if [ "$OLD" = "$NEW" ]; then
  set -- $THREADS
  [ $# = 2 ] || { echo "one binary: THREADS must name two thread counts" >&2; exit 2; }
  a=(1 "$OLD" "$1") b=(1 "$NEW" "$2")
else
  a=(1 "$OLD" "$THREADS") b=(1 "$NEW" "$THREADS")
fi
printf 'scene %s, state %s, %s steps; load before: %s\n' "$SCENE" "$STATE" "$STEPS" "$(uptime | sed 's/.*load/load/')"
ratios=""
for R in $(seq 1 "$ROUNDS"); do
  x=$(rate "${a[1]}" "${a[2]}")
  y=$(rate "${b[1]}" "${b[2]}")
  r=$(python3 -c "print($y / $x)")
  printf 'round %d: %s threads %.4g, %s threads %.4g p-steps/s, ratio %.3f\n' "$R" "${a[2]}" "$x" "${b[2]}" "$y" "$r"
  ratios="$ratios $r"
done
python3 -c "import statistics,sys; print('median ratio %.3f' % statistics.median(map(float, sys.argv[1:])))" $ratios
printf 'load after: %s\n' "$(uptime | sed 's/.*load/load/')"
