#!/usr/bin/env bash
# Continue the experiment's held-out long runs (issue 39) from the checkpoints committed in
# docs/results/experiment/long-runs/seedN/, on a machine that does not hold the runs' own
# folders (a new session's machine). Each lane is a list of SEED:T pairs, run one after the
# other; T is the simulated time (s) to reach (t3 = 2 s, so 402 is t3 + 400 s). Two lanes at
# most, so that two one-thread simulations share the 2 cores.
#
#   scripts/experiment/continue-long-runs.sh OUT "1:402" "3:402 2:402"
#
# T may not be below the run's own run.duration (its scene.toml): a resume only extends.
#
# STRIPES names the binary. The committed checkpoints are of sample revision 7 (builds from
# 58a8f67 up to 40dfd42's parent, e.g. 9196c57); a build of another revision refuses them
# and says so (long-runs/README.md, "To continue").
#
# A seed whose OUT/seedN/checkpoint.bin exists goes on from it; otherwise its folder is made
# from the committed files: scene.toml, checkpoint.bin, thermo.csv's column line, and a sparse
# snapshots.bin (the committed header, then zeros up to 2 GB). The frames before the committed
# checkpoint are therefore zeros: analyse only the frames this continuation writes
# (scripts/experiment/heldout.py reads them, and refuses a frame of zeros).
#
# The resume rule of `stripes run --resume` keeps every key of the run's scene except
# run.duration (and the thread count and checkpoint interval): the continuation is the same
# trajectory, bit for bit, as the run that wrote the checkpoint (docs/outputs.md).
set -u
out=$1
shift
bin=${STRIPES:-target/release/stripes}
src=docs/results/experiment/long-runs
mkdir -p "$out"
log() { echo "$(date -u +%FT%TZ) $*" >> "$out/queue.log"; }

prepare() {
    local seed=$1 dir="$out/seed$1"
    if [ -f "$dir/checkpoint.bin" ]; then return; fi
    mkdir -p "$dir"
    cp "$src/seed$seed/scene.toml" "$src/seed$seed/checkpoint.bin" "$dir/"
    cp "$src/seed$seed/thermo-header.csv" "$dir/thermo.csv"
    cp "$src/seed$seed/snapshots-header.bin" "$dir/snapshots.bin"
    truncate -s 2G "$dir/snapshots.bin"
    log "seed $seed prepared from $src/seed$seed ($(cat "$src/seed$seed/status.txt"))"
}

extend() {
    local seed=$1 to=$2 dir="$out/seed$1"
    prepare "$seed"
    log "seed $seed to $to s start"
    local start=$(date +%s)
    nice "$bin" run "$dir/scene.toml" --out "$dir" --resume --quiet --set run.duration="$to" \
        > "$out/seed$seed.to$to.run.json" 2> "$out/seed$seed.to$to.err" \
        || { log "seed $seed to $to s FAILED: $(tail -c 400 "$out/seed$seed.to$to.err")"; return 1; }
    log "seed $seed to $to s done wall_s $(( $(date +%s) - start ))"
}

lane() {
    for job in $1; do extend "${job%%:*}" "${job##*:}" || return 1; done
}

for spec in "$@"; do lane "$spec" & done
wait
log "lanes done"
