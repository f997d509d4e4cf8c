#!/bin/bash
# The experiment's A/d (about 4.7: A = 3.6 mm with the thesis' grains, mean diameter 0.765 mm)
# and packing (0.35: 3043 grains on 0.2 m x 0.02 m), 3 Hz, 20 s = 60 periods, seeds 1 and 2.
# Usage (from the repository root): bash scripts/thesis-scale/experiment-ad/run.sh [stripes]
set -euo pipefail
B=${1:-target/release/stripes}
for s in 1 2; do
  $B run scenes/stripes.toml --out out/experiment-ad/seed-$s --quiet \
    --set box.length=0.2 --set particles.count=3043 --set drive.amplitude=0.0036 --set run.duration=20 \
    --set run.threads=1 --set run.seed=$s
  $B analyze out/experiment-ad/seed-$s
done
