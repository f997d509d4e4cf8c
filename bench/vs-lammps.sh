#!/usr/bin/env bash
# Side-by-side speed of stripes and LAMMPS on the thesis tray (scenes/thesis-reference.toml):
# same N, radii, box (length scaled with N at the thesis packing), dt = 8e-6 s, drive
# (20 Hz, 25 mm), number of steps; 1 and 2 threads (LAMMPS: MPI ranks). Prints particle-steps
# per second of the stepping loop for each and the ratio stripes / LAMMPS, then one JSON line.
#
#   bench/vs-lammps.sh                 # N = 4000, 10000 steps
#   N=16000 STEPS=5000 bench/vs-lammps.sh
#
# Both codes start from the same kind of state (one layer on a lattice at rest on the floor,
# random vx, vy in +-5 mm/s, no relaxation); see bench/README.md for the model mapping.
set -euo pipefail
cd "$(dirname "$0")/.."
N=${N:-4000}
STEPS=${STEPS:-10000}
THREADS=${THREADS:-"1 2"}
LENGTH=$(python3 -c "print(0.4 * $N / 4000)")
DURATION=$(python3 -c "print($STEPS * 8e-6)")

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
python3 bench/lammps/make_data.py "$N" "$LENGTH" 0.02 1 "$work/tray.data"

json="["
printf '%8s %8s %18s %18s %8s\n' N threads "stripes p-steps/s" "LAMMPS p-steps/s" ratio
for T in $THREADS; do
  OMP_NUM_THREADS=1 mpirun --allow-run-as-root --oversubscribe -np "$T" lmp -in bench/lammps/in.tray \
    -var data "$work/tray.data" -var steps "$STEPS" -log "$work/lmp$T.log" -screen none > /dev/null
  loop=$(awk '/^Loop time/ {print $4}' "$work/lmp$T.log" | tail -1)
  atoms=$(awk '/^ATOMS/ {print $2}' "$work/lmp$T.log" | tail -1)
  [ "$atoms" = "$N" ] || { echo "LAMMPS lost atoms: $atoms of $N" >&2; exit 1; }
  lmp_rate=$(python3 -c "print($N * $STEPS / $loop)")

  summary=$(target/release/stripes run scenes/thesis-reference.toml --quiet --out "$work/stripes$T" --samples "$work/samples" \
    --set particles.count="$N" --set box.length="$LENGTH" --set prepare.duration=0 \
    --set run.duration="$DURATION" --set run.threads="$T" --set run.checkpoint_interval=0 | tail -1)
  our_rate=$(python3 -c "import json,sys; print(json.loads(sys.argv[1])['particle_steps_per_s'])" "$summary")
  ratio=$(python3 -c "print($our_rate / $lmp_rate)")
  printf '%8d %8d %18.4g %18.4g %8.2f\n' "$N" "$T" "$our_rate" "$lmp_rate" "$ratio"
  json="$json{\"n\":$N,\"steps\":$STEPS,\"threads\":$T,\"stripes\":$our_rate,\"lammps\":$lmp_rate,\"ratio\":$ratio},"
done
echo "${json%,}]"
