#!/usr/bin/env bash
# Rung 1 of the coarse model's validation ladder (issue 40): the automaton against the DEM's
# seed spread on the stripe scene (0.1 m), on seeds not used to measure the parameter file.
#
#   scripts/coarse-model/rung1.sh DEM PARAMS OUT DURATION RULE SEED...
#
# DEM: a folder of `stripes run scenes/stripes.toml --set run.seed=S --out DEM/seedS` runs (their
# prepared samples cached in DEM/out/samples, as `stripes run` leaves them when started in DEM);
# PARAMS: the automaton.toml `stripes mechanism RUN --coarse-only` wrote on the fit run;
# DURATION: simulated seconds of each automaton run (the DEM runs are analysed over their own
# length); RULE: measured or swing. Writes OUT/RULE-seedS and prints the table
# (scripts/coarse-model/rung1_table.py).
set -eu
dem=$1 params=$2 out=$3 duration=$4 rule=$5
shift 5
bin=${STRIPES:-target/release/stripes}
mkdir -p "$out"
for s in "$@"; do
    if [ ! -f "$dem/seed$s/analysis-rung1/summary.json" ]; then
        "$bin" analyze "$dem/seed$s" --out "$dem/seed$s/analysis-rung1" > /dev/null 2>> "$out/errors.log"
    fi
    start=$(date +%s.%N)
    "$bin" automaton scenes/stripes.toml --set automaton.parameters="$params" --rule "$rule" \
        --set run.seed="$s" --set run.duration="$duration" --out "$out/$rule-seed$s" --force \
        --sample-cache "$dem/out/samples" --quiet > "$out/$rule-seed$s.json" 2>> "$out/errors.log"
    echo "$rule seed $s: $(echo "$(date +%s.%N) - $start" | bc) s wall" >> "$out/wall.log"
done
python3 scripts/coarse-model/rung1_table.py "$dem" "$out" "$rule" "$@"
