#!/usr/bin/env bash
# Side-by-side speed of stripes and LAMMPS on the thesis tray (scenes/thesis-reference.toml):
# the same grains (stripes writes its starting state as a LAMMPS data file, --lammps-data),
# dt = 8e-6 s, box (length scaled with N at the thesis packing), drive (20 Hz, 25 mm) and
# number of steps; 1 and 2 threads (LAMMPS: MPI ranks). Prints particle-steps per second of
# the stepping loop for each and the ratio stripes / LAMMPS, then one JSON line.
#
#   bench/vs-lammps.sh                       # N = 4000, 10000 steps from the lattice at rest
#   N=16000 STEPS=5000 bench/vs-lammps.sh
#   STATE=gas bench/vs-lammps.sh             # from the thesis scene's gas (t = 10 s, N = 4000)
#   ROUNDS=5 bench/vs-lammps.sh              # rounds per thread count (default 3), median ratio
#   STRIPES=/path/to/old/stripes bench/vs-lammps.sh   # another build of stripes
#
# STATE=lattice (default): one layer on a lattice at rest on the floor, random vx, vy in
# +-5 mm/s, no relaxation (prepare.duration = 0). STATE=gas: the state of the thesis scene
# (velocity Verlet, dt = 8e-6 s) after 10 s of shaking, when the layer is a gas of flying and
# colliding grains; stripes prepares it once in out/bench-gas (about 5 minutes on 2 cores) and
# both codes continue from it. See bench/README.md for the model mapping.
set -euo pipefail
# Every step on the threads asked for: a run's pace (particles/src/pace.rs) would otherwise
# step on fewer threads where fewer are faster, and the table would not show the team's rate.
export STRIPES_FIXED_TEAM=1
cd "$(dirname "$0")/.."
# The stripes binary (default: this checkout's release build), e.g. an older build to compare.
STRIPES=${STRIPES:-target/release/stripes}
STATE=${STATE:-lattice}
N=${N:-4000}
STEPS=${STEPS:-10000}
THREADS=${THREADS:-"1 2"}
ROUNDS=${ROUNDS:-3}
DT=8e-6

if ! command -v lmp > /dev/null; then
  echo "installing LAMMPS (apt-get install lammps)" >&2
  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq lammps > /dev/null
fi
if ! command -v mpirun > /dev/null; then
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq openmpi-bin > /dev/null
fi
cargo build --release -q
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

case "$STATE" in
  lattice)
    LENGTH=$(python3 -c "print(0.4 * $N / 4000)")
    DURATION=$(python3 -c "print($STEPS * $DT)")
    ;;
  gas)
    [ "$N" = 4000 ] || { echo "STATE=gas runs the thesis scene itself: N = 4000" >&2; exit 2; }
    LENGTH=0.4
    GAS=out/bench-gas
    # A checkpoint of an older sample revision (or scene) does not resume: prepare it again.
    if [ -f "$GAS/checkpoint.bin" ]; then
      cp -a "$GAS" "$work/probe"
      "$STRIPES" run "$work/probe/scene.toml" --resume --quiet --out "$work/probe" \
        --set run.duration=10 > /dev/null 2>&1 || rm -rf "$GAS"
      rm -rf "$work/probe"
    fi
    if [ ! -f "$GAS/checkpoint.bin" ]; then
      echo "preparing the gas state: the thesis scene for 10 s in $GAS" >&2
      "$STRIPES" run scenes/thesis-reference.toml --quiet --out "$GAS" \
        --set run.duration=10 --set run.checkpoint_interval=10 > /dev/null
    fi
    DURATION=$(python3 -c "print(10 + $STEPS * $DT)")
    ;;
  *) echo "STATE must be lattice or gas, got $STATE" >&2; exit 2 ;;
esac

# stripes, writing the state it starts from for LAMMPS.
ours() {
  local T=$1 dir="$work/stripes$1"
  if [ "$STATE" = gas ]; then
    cp -a "$GAS" "$dir"
    "$STRIPES" run "$dir/scene.toml" --resume --quiet --out "$dir" --lammps-data "$work/tray.data" \
      --set run.duration="$DURATION" --set run.threads="$T" --set run.checkpoint_interval=0 2>> "$work/stripes.err" | tail -1
  else
    "$STRIPES" run scenes/thesis-reference.toml --quiet --out "$dir" --lammps-data "$work/tray.data" \
      --set particles.count="$N" --set box.length="$LENGTH" --set prepare.duration=0 \
      --set run.duration="$DURATION" --set run.threads="$T" --set run.checkpoint_interval=0 2>> "$work/stripes.err" | tail -1
  fi
}

json="["
# Rounds alternate the two codes, so that both see the same spell of this shared machine (its
# speed drifts by 25% over minutes); the summary line per thread count is the median of the
# rounds' ratios, with the median rates.
printf '%8s %8s %8s %6s %18s %18s %8s\n' state N threads round "stripes p-steps/s" "LAMMPS p-steps/s" ratio
for T in $THREADS; do
  rows=""
  for R in $(seq 1 "$ROUNDS"); do
    rm -rf "$work/stripes$T"
    summary=$(ours "$T")
    our_rate=$(python3 -c "import json,sys; print(json.loads(sys.argv[1])['particle_steps_per_s'])" "$summary")

    OMP_NUM_THREADS=1 mpirun --allow-run-as-root --oversubscribe -np "$T" lmp -in bench/lammps/in.tray \
      -var data "$work/tray.data" -var steps "$STEPS" -log "$work/lmp$T.log" -screen none > /dev/null \
      || { tail -3 "$work/lmp$T.log" >&2; exit 1; }
    loop=$(awk '/^Loop time/ {print $4}' "$work/lmp$T.log" | tail -1)
    atoms=$(awk '/^ATOMS/ {print $2}' "$work/lmp$T.log" | tail -1)
    [ "$atoms" = "$N" ] || { echo "LAMMPS lost atoms: $atoms of $N" >&2; exit 1; }
    lmp_rate=$(python3 -c "print($N * $STEPS / $loop)")

    ratio=$(python3 -c "print($our_rate / $lmp_rate)")
    printf '%8s %8d %8d %6d %18.4g %18.4g %8.2f\n' "$STATE" "$N" "$T" "$R" "$our_rate" "$lmp_rate" "$ratio"
    rows="$rows $our_rate,$lmp_rate,$ratio"
  done
  line=$(python3 - "$STATE" "$N" "$STEPS" "$T" $rows <<'PY'
import json, statistics, sys
state, n, steps, t = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
rounds = [tuple(map(float, r.split(","))) for r in sys.argv[5:]]
med = [statistics.median(c) for c in zip(*rounds)]
print(f"{state:>8} {n:8d} {t:8d} {'median':>6} {med[0]:18.4g} {med[1]:18.4g} {med[2]:8.2f}")
print(json.dumps({"state": state, "n": n, "steps": steps, "threads": t, "rounds": len(rounds),
                  "stripes": med[0], "lammps": med[1], "ratio": med[2],
                  "ratios": [r[2] for r in rounds]}))
PY
)
  echo "$line" | head -1
  json="$json$(echo "$line" | tail -1),"
done
echo "${json%,}]"
