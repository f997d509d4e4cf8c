#!/bin/bash
# Rough spheres in a 2D vibrating box (issue 27 section 3) with the event-driven model, on
# scenes/vibrated-box.toml. Each block writes one sweep directory here.
# Usage: bash scripts/vibrated-box/run.sh [path/to/stripes] (from the repository root).
set -euo pipefail
B=${1:-target/release/stripes}
D=docs/results/vibrated-box
S=scenes/vibrated-box.toml
T="--threads ${THREADS:-1} --force --quiet"
# A block whose tables are already here is skipped, so an interrupted script resumes.
have() { [ -s "$D/$1.json" ] && [ -f "$D/$1/means.csv" ]; }
# H against V = A0 2 pi f at 40, 100 and 500 Hz (drive.peak_speed sets A0 at each frequency).
# From V = 0.05 m/s: at 0.025 m/s and 40 Hz, Gamma = 0.64 and the grains rest on the floor.
have speed || $B events-sweep $S $T --out $D/speed --seeds 5 --log \
  --vary drive.peak_speed=0.05,0.1,0.2,0.4,0.8,1.6,3.2 --vary drive.frequency=40,100,500 \
  --set box.height=0.4 > $D/speed.json
# mu from 0 to 20 and beta0 from -1 to 1, at 100 Hz and V = 0.2 m/s.
have friction || $B events-sweep $S $T --out $D/friction --seeds 5 --vary rules.pair.mu=0,0.05,0.1,0.2,0.5,1,2,5,20 \
  --vary rules.pair.beta0=0,0.5,1 > $D/friction.json
have roughness || $B events-sweep $S $T --out $D/roughness --seeds 5 --vary rules.pair.beta0=-1,-0.5,0,0.5,1 > $D/roughness.json
# N and L at fixed N / L = 5 grains per mm.
for n in 25 50 100 200; do
  have size-$n || $B events-sweep $S $T --out $D/size-$n --seeds 5 --vary particles.species.0.count=$n \
    --set box.width=$(python3 -c "print($n/5*1e-3)") > $D/size-$n.json
done
# Rough side walls that move with the bottom (e = 0.9, mu = 0.5, beta0 = 0.5, as the pairs).
have rough-sides || $B events-sweep $S $T --out $D/rough-sides --seeds 5 --vary drive.frequency=100 \
  --set box.side_walls=with-floor --set rules.side.e=0.9 --set rules.side.mu=0.5 --set rules.side.beta0=0.5 > $D/rough-sides.json
have smooth-sides || $B events-sweep $S $T --out $D/smooth-sides --seeds 5 --vary drive.frequency=100 > $D/smooth-sides.json
# The DEM's collisions as the pairs' rule: the restitution table of the stripe scene's laws,
# against the constant Walton rule fitted to it (e = 0.89, mu = 0.7, beta0 = 0) and the scene's.
have dem-table/sweep || { $B collide --table --scene scenes/stripes.toml --g-n 0.01,0.02,0.05,0.1,0.2,0.5,1,2 \
    --out $D/dem-table --force > /dev/null
  $B events-sweep $D/dem-table/scene.toml $T --out $D/dem-table/sweep --seeds 5 \
    --vary drive.peak_speed=0.2,0.8 > $D/dem-table/sweep.json; }
have dem-table/fitted || $B events-sweep $S $T --out $D/dem-table/fitted --seeds 5 \
  --vary drive.peak_speed=0.2,0.8 --set rules.pair.e=0.89 --set rules.pair.mu=0.7 --set rules.pair.beta0=0 \
  > $D/dem-table/fitted.json
