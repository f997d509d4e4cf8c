#!/bin/bash
# The thesis-scale sweep: the stripe scene (3 Hz, 10 mm, packing 0.46) on the thesis' 0.4 m
# tray with one thing changed per run: the amplitude (6, 15 mm), the packing (0.35, 0.55) or
# the tray length (0.3, 0.5 m, at packing 0.46). One thread per run, two runs at a time.
# The amplitude runs last 6 s (seed 1); the packing and tray runs 4 s (seeds 1 and 2): the
# machine's budget on 2026-11-27.
# Then the tables and fits, beside the reference's five 100-period seeds cut at 3, 4 and 6 s:
#   python3 scripts/thesis-scale/sweep/collect.py OUT > docs/results/thesis-scale/sweep/tables.md
set -e
OUT=${OUT:-out/thesis-scale-sweep}
one() {  # NAME SEED DURATION --set ...
  local name=$1 seed=$2 duration=$3; shift 3
  stripes run scenes/stripes.toml --out "$OUT/$name-s$seed" --set run.duration="$duration" \
    --set run.snapshots_per_period=4 --set run.threads=1 --set run.seed="$seed" "$@"
  stripes analyze "$OUT/$name-s$seed"
}
one A6 1 6 --set box.length=0.4 --set particles.count=8000 --set drive.amplitude=0.006 &
one A15 1 6 --set box.length=0.4 --set particles.count=8000 --set drive.amplitude=0.015
wait
for s in 1 2; do
  one L0.3 $s 4 --set box.length=0.3 --set particles.count=6000 &
  one phi0.35 $s 4 --set box.length=0.4 --set particles.count=6087
  wait
  one phi0.55 $s 4 --set box.length=0.4 --set particles.count=9565 &
  one L0.5 $s 4 --set box.length=0.5 --set particles.count=10000
  wait
done
