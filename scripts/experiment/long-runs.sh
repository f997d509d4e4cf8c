#!/usr/bin/env bash
# The experiment's held-out runs (issue 39): the chosen fit on seeds 1, 2, 3, each first to
# t3 + 10 s (t3: the start of the 3 Hz / 10 mm stage), analysed there for the early targets
# only (scripts/experiment/early.py; the frames after t3 + 10 s do not exist yet when it
# reads), then continued with --resume to t3 + 400 s. Two lanes, so at most two simulation
# processes at once, each on one thread:
#   lane A: seed 1 early, seed 3 early, seed 1 to 400 s, seed 3 to 400 s
#   lane B: seed 2 early, seed 2 to 400 s, seed 2 to 3400 s
# The held-out counts (100, 1400, 3400 s) and the end-wall zones are not read here.
#
#   scripts/experiment/long-runs.sh OUT T3 [KEY=VALUE ...]     (the fit's --set values)
#
# One snapshot per period (the scene's camera rate: the camera's strobe frames, the +A turning
# points, are the same frames the fit's four per period give it; an hour at four per period
# would be 4.7 GB a run, more than the analysis can hold in memory).
set -u
out=$1 t3=$2
shift 2
bin=${STRIPES:-target/release/stripes}
sets=(--set run.threads=1 --set run.snapshots_per_period=1 --set contact.rolling=sds)
for kv in "$@"; do sets+=(--set "$kv"); done
mkdir -p "$out"
at() { python3 -c "print(round($t3 + $1, 6))"; }
log() { echo "$(date -u +%FT%TZ) $*" >> "$out/queue.log"; }

early() {
    local seed=$1 dir="$out/seed$1"
    if [ -f "$out/seed$seed.early.json" ]; then return; fi
    log "seed $seed early start"
    local start=$(date +%s)
    nice "$bin" run scenes/experiment.toml --out "$dir" --sample-cache "$out/samples" --quiet \
        --set run.seed="$seed" --set run.duration="$(at 10)" "${sets[@]}" > "$out/seed$seed.early.run.json" \
        || { log "seed $seed early FAILED"; return 1; }
    nice "$bin" analyze "$dir" --out "$out/seed$seed-early-analysis" --force --quiet \
        --top-view "$(at 0.05),$(at 2),$(at 4),$(at 6),$(at 10)" > "$out/seed$seed.early.analysis.json"
    # early.py reads RUN/analysis: point it at the early analysis.
    ln -sfn "../seed$seed-early-analysis" "$dir/analysis"
    python3 scripts/experiment/early.py "$dir" > "$out/seed$seed.early.json"
    rm -f "$dir/analysis"
    log "seed $seed early done wall_s $(( $(date +%s) - start )) $(cat "$out/seed$seed.early.json")"
}

extend() {
    local seed=$1 to=$2 dir="$out/seed$1"
    log "seed $seed to t3+$to start"
    local start=$(date +%s)
    nice "$bin" run "$dir/scene.toml" --out "$dir" --resume --quiet --set run.duration="$(at "$to")" \
        > "$out/seed$seed.to$to.run.json" || { log "seed $seed to t3+$to FAILED"; return 1; }
    log "seed $seed to t3+$to done wall_s $(( $(date +%s) - start ))"
}

( early 1; early 3; extend 1 400; extend 3 400 ) &
( early 2; extend 2 400; extend 2 3400 ) &
wait
log "queue done"
