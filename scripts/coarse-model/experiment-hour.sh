#!/usr/bin/env bash
# The experiment's hour on the coarse model (issue 40, step 4): the automaton's `swing` rule
# with a parameter file measured on the experiment tray's DEM, for several seeds, in two
# lanes (2 cores), then the camera count at the experiment's times
# (scripts/coarse-model/experiment_hour_table.py).
#
#   scripts/coarse-model/experiment-hour.sh SCENE PARAMS OUT EVERY SEED...
#
# SCENE: the experiment's tray with one drive (3 Hz / 10 mm; the automaton runs no schedule,
# and starts from the DEM's prepared, homogeneous sample, as the fluidising stage leaves the
# layer); EVERY: automaton.snapshot_every (periods). Wall times in OUT/wall.log.
set -eu
scene=$1 params=$2 out=$3 every=$4
shift 4
bin=${STRIPES:-target/release/stripes}
mkdir -p "$out"
one() {
    local s=$1 start
    start=$(date +%s.%N)
    "$bin" automaton "$scene" --rule swing --set automaton.parameters="$params" --set run.seed="$s" \
        --set run.duration=3600 --set automaton.snapshot_every="$every" --out "$out/seed$s" --force \
        --sample-cache "$out/samples" --quiet > "$out/seed$s.json" 2> "$out/seed$s.err"
    echo "seed $s: $(echo "$(date +%s.%N) - $start" | bc) s wall" >> "$out/wall.log"
}
# Two lanes; the sample cache is shared (each seed prepares its own sample once).
seeds=("$@")
start=$(date +%s.%N)
half=$(( (${#seeds[@]} + 1) / 2 ))
( for s in "${seeds[@]:0:$half}"; do one "$s"; done ) &
( for s in "${seeds[@]:$half}"; do one "$s"; done ) &
wait
echo "all ${#seeds[@]} seeds: $(echo "$(date +%s.%N) - $start" | bc) s wall" >> "$out/wall.log"
python3 scripts/coarse-model/experiment_hour_table.py "$out" "${seeds[@]}"
