#!/bin/bash
# Issue 44, the mixture's plateau: the candidates that were left untested (the drive's
# waveform, the aspect ratio and filling of the box, 2D against 3D rotation), each at Gamma
# 56 and 160 (A = 3.5 d fixed, the frequency varied, as the paper does), 2 seeds of 60 s
# after a 5 s transient; and the Gamma 240/320 runs of ../gamma-high/ again with today's
# collapse detector (3 seeds of 200 s, as before).
# Each candidate run keeps its summary (runs/<name>-G<Gamma>-s<seed>.json) and its free-time
# densities (runs/<...>.free_times.csv, whose elastic column gives the mean collision rate
# per species); the run's other files go to $WORK (default /tmp/stripes-plateau), not
# into the repository. `python3 scripts/mixture/plateau/table.py` then writes table.csv.
# A run whose summary exists is skipped, so an interrupted script resumes.
# Usage: bash scripts/mixture/plateau/run.sh [path/to/stripes] (from the repository root).
set -euo pipefail
B=${1:-target/release/stripes}
D=docs/results/mixture/plateau
S=scenes/mixture.toml
W=${WORK:-/tmp/stripes-plateau}
mkdir -p $D/runs $W
freq() { python3 -c "import math,sys; print(f'{math.sqrt(float(sys.argv[1])*9.81/0.0056)/(2*math.pi):.4f}')" "$1"; }
candidate() { # name, then extra --set options
  local name=$1; shift
  for G in 56 160; do
    for seed in 1 2; do
      local run=$name-G$G-s$seed
      [ -s $D/runs/$run.json ] && continue
      nice -n 10 $B events $S --force --quiet --out $W/$run --set drive.frequency=$(freq $G) \
        --set run.duration=60 --set run.transient=5 --set run.seed=$seed "$@" > $W/$run.json
      cp $W/$run/free_times.csv $D/runs/$run.free_times.csv
      mv $W/$run.json $D/runs/$run.json
    done
  done
}
# The reference (sinusoidal walls, 48 d x 32 d, 150 + 150) on the same footing.
candidate sine
# The drive: Barrat and Trizac's sawtooth walls (standing still, pushing at A 2 pi f).
candidate sawtooth --set drive.waveform=sawtooth
# Rotation: disks (q = 1/2, 2D) against spheres (q = 2/5), and no coupling to rotation (mu = 0).
candidate disks --set particles.shape=disk
candidate smooth --set rules.pair.mu=0
# The restitution: constant e for every impact (the theory's), without the paper's e -> 1
# below v0 = sqrt(g d) (the scene without its rules.pair.v0). Without it the gas collapses
# (a true collapse, approach speeds 6e-17 m/s, at 3.5 s), so the runs keep the minimum
# rebound speed of 5 mm/s of the ablations above.
sed '/^v0 = /d' $S > $W/mixture-constant-e.toml
S=$W/mixture-constant-e.toml candidate constant-e --set guard.min_rebound_speed=0.005
# The aspect ratio at the paper's area fraction: twice as wide (96 d x 32 d, 300 + 300) and
# half as wide (24 d x 32 d, 75 + 75). The wide box collapses onto a wall without a guard
# (one grain, approach speeds 2e-10 m/s, at 2.2 s), so it keeps the minimum rebound speed
# of 5 mm/s, as the 300 + 300 segregation runs do.
candidate wide --set box.width=0.1536 --set particles.species.0.count=300 --set particles.species.1.count=300 \
  --set guard.min_rebound_speed=0.005
candidate narrow --set box.width=0.0384 --set particles.species.0.count=75 --set particles.species.1.count=75
# The filling between the paper's two (75 + 75 and 150 + 150): 100 + 100.
candidate fill-100 --set particles.species.0.count=100 --set particles.species.1.count=100
# Gamma 240 and 320 with today's collapse detector (slow collisions only).
[ -s $D/gamma-high.json ] || nice -n 10 $B events-sweep $S --threads 1 --force --quiet --out $D/gamma-high --seeds 3 \
  --vary drive.frequency=$(freq 240),$(freq 320) --set run.duration=200 --set run.transient=5 > $D/gamma-high.json
