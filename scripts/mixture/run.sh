#!/bin/bash
# The binary mixture paper (seed 001) with the event-driven model, on scenes/mixture.toml:
# long runs for the profiles (Figs 2, 5, 6-9), a sweep over Gamma at fixed amplitude (Fig 3),
# the second set of restitutions (Fig 4), two ablations (mu = 0; the heavy species' wall
# restitution 0.4) and the tall box of section 4 (Fig 11). Each block writes one directory
# here and is skipped when its summary is already written, so an interrupted script resumes.
# Usage: bash scripts/mixture/run.sh [path/to/stripes] (from the repository root).
set -euo pipefail
B=${1:-target/release/stripes}
D=docs/results/mixture
S=scenes/mixture.toml
have() { [ -s "$D/$1.json" ]; }
long="--set run.duration=300 --set run.transient=5"
# The reference scene, four seeds of 300 s (15000 periods each).
for seed in 1 2 3 4; do
  have reference-$seed || $B events $S --force --quiet --out $D/reference-$seed $long --set run.seed=$seed > $D/reference-$seed.json
done
# Fig 4: the heavy grains the more inelastic (r11 = 0.7, r12 = 0.81, r22 = 0.93).
have swapped || $B events $S --force --quiet --out $D/swapped $long --set "rules.pair.e=[0.7, 0.81, 0.93]" > $D/swapped.json
# Ablations the paper reports as changing little in the bulk.
have smooth || $B events $S --force --quiet --out $D/smooth $long --set rules.pair.mu=0 > $D/smooth.json
# With e = 0.4 at the walls heavy grains collapse onto the floor (runs stopped at 0.42 s, and
# at 6.6 s with the pairs' v0 rule on the walls too); the minimum rebound speed of 5 mm/s,
# whose cost on the reference scene is under 1.5 % (docs/scenes.md), keeps them hopping.
have heavy-wall-e04 || $B events $S --force --quiet --out $D/heavy-wall-e04 $long \
  --set "rules.floor.e=[0.4, 1.0]" --set "rules.lid.e=[0.4, 1.0]" \
  --set guard.min_rebound_speed=0.005 > $D/heavy-wall-e04.json
# Section 4: the tall box, 48 d x 64 d, 300 + 300 grains.
have tall || $B events $S --force --quiet --out $D/tall $long --set box.height=0.1024 \
  --set particles.species.0.count=300 --set particles.species.1.count=300 > $D/tall.json
# Fig 3: the bulk ratio against Gamma = A (2 pi f)^2 / g at A = 3.5 d, 4 seeds of 200 s.
freqs=$(python3 -c "import math; print(','.join(f'{math.sqrt(G*9.81/0.0056)/(2*math.pi):.4f}' for G in [10,20,30,40,56,80,120,160]))")
have gamma || $B events-sweep $S --threads ${THREADS:-1} --force --quiet --out $D/gamma --seeds 4 --log \
  --vary drive.frequency=$freqs --set run.duration=200 --set run.transient=5 > $D/gamma.json
# Fig 3, continued: does the bulk ratio saturate? Gamma = 240 and 320, 3 seeds of 200 s.
freqs=$(python3 -c "import math; print(','.join(f'{math.sqrt(G*9.81/0.0056)/(2*math.pi):.4f}' for G in [240,320]))")
have gamma-high || $B events-sweep $S --threads ${THREADS:-1} --force --quiet --out $D/gamma-high --seeds 3 \
  --vary drive.frequency=$freqs --set run.duration=200 --set run.transient=5 > $D/gamma-high.json
# Fig 3's upper triangles: 75 + 75 grains, the same Gamma values, 2 seeds of 200 s.
freqs=$(python3 -c "import math; print(','.join(f'{math.sqrt(G*9.81/0.0056)/(2*math.pi):.4f}' for G in [10,20,30,40,56,80,120,160]))")
have gamma-half || $B events-sweep $S --threads ${THREADS:-1} --force --quiet --out $D/gamma-half --seeds 2 --log \
  --vary drive.frequency=$freqs --set particles.species.0.count=75 --set particles.species.1.count=75 \
  --set run.duration=200 --set run.transient=5 > $D/gamma-half.json
