#!/bin/bash
# Replays the run of ../gamma-high/ that stopped at Gamma 320, seed 3 (t = 83.1 s), at the
# commit that produced it (d8281df), with replay-d8281df.patch: the old detector (every
# collision counted) only reports where it would have stopped, with the approach speeds of
# the burst, and today's detector (slow collisions only) stops the run. Builds in $WORK
# (default /tmp/stripes-replay); a few minutes to build, about 2 minutes of CPU to run.
# Usage: bash scripts/mixture/plateau/replay.sh (from the repository root).
set -euo pipefail
W=${WORK:-/tmp/stripes-replay}
P=$(pwd)/scripts/mixture/plateau/replay-d8281df.patch
mkdir -p $W/src
git archive d8281df | tar -x -C $W/src
(cd $W/src && patch -p1 < $P && cargo build --release --bin stripes)
nice -n 10 $W/src/target/release/stripes events $W/src/scenes/mixture.toml --force --quiet --out $W/g320-s3 \
  --set drive.frequency=119.1614 --set run.seed=3 --set run.duration=90 --set run.transient=5 \
  > $W/g320-s3.json 2> $W/g320-s3.err
cat $W/g320-s3.err
