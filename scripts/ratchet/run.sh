#!/bin/bash
# The ratchet paper's sweeps (seed 004, Figs 6-12) with the event-driven model, on
# scenes/ratchet.toml. Each block writes one sweep directory here (runs.csv, means.csv,
# plots). Usage: bash scripts/ratchet/run.sh [path/to/stripes] (from the repository root).
set -euo pipefail
B=${1:-target/release/stripes}
D=docs/results/ratchet
S=scenes/ratchet.toml
T="--threads ${THREADS:-1} --force --quiet"
# A block whose tables are already here is skipped, so an interrupted script resumes.
have() { [ -s "$D/$1.json" ] && { [ -f "$D/$1/means.csv" ] || [ -f "$D/$1/summary.json" ]; }; }
# A layer of the paper's 144 mm cell holds about 70 disks; its 60 mm cell about 29.2.
layers60="10,20,31,51,82,123,146,204,292"   # n = 0.35, 0.7, 1.05, 1.75, 2.8, 4.2, 5, 7, 10

# Cheapest and most quoted first: the reference points, the onset, then the sweeps.
# The two reference points (Figs 13-14), 5 seeds of 50 s each.
have reference-positive || $B events-sweep $S $T --out $D/reference-positive --seeds 5 --vary base.tooth_height=0.003 > $D/reference-positive.json
have reference-negative || $B events-sweep $S $T --out $D/reference-negative --seeds 5 --vary base.tooth_height=0.006 \
  --set base.asymmetry=0.25 --set drive.frequency=30 --set particles.species.0.count=25 > $D/reference-negative.json
# Fig 11: the onset; <v_x> against the frequency (Gamma = A (2 pi f)^2 / g) at h = 3 mm,
# a = 0.1, n = 0.7 (20 disks), 60 mm, 30 s. Gamma 1.0-2.6 in steps of about 0.1.
freqs=$(python3 -c "import math; print(','.join(f'{math.sqrt(G*9.81/0.002)/(2*math.pi):.4f}' for G in [1.0,1.1,1.2,1.25,1.3,1.35,1.4,1.5,1.6,1.8,2.0,2.3,2.6]))")
have fig11-onset || $B events-sweep $S $T --out $D/fig11-onset --seeds 7 \
  --vary drive.frequency=$freqs --set particles.species.0.count=20 \
  --set box.width=0.06 --set run.duration=30 --set run.transient=5 > $D/fig11-onset.json
# Fig 6: <v_x> against the asymmetry at h = 3, 5, 9 mm; n = 1 (70 disks), 25 Hz, 50 s.
have fig6-asymmetry || $B events-sweep $S $T --out $D/fig6-asymmetry --seeds 2 \
  --vary base.asymmetry=0,0.05,0.1,0.15,0.2,0.25,0.3,0.35,0.4,0.45,0.5 \
  --vary base.tooth_height=0.003,0.005,0.009 --set particles.species.0.count=70 > $D/fig6-asymmetry.json
# Fig 7: <v_x> against the tooth height at a = 0.05 and 0.333; n = 1, 25 Hz, 50 s.
have fig7-height || $B events-sweep $S $T --out $D/fig7-height --seeds 2 \
  --vary base.tooth_height=0.001,0.002,0.003,0.004,0.005,0.006,0.008,0.010,0.012,0.016 \
  --vary base.asymmetry=0.05,0.333 --set particles.species.0.count=70 --set box.height=0.1 > $D/fig7-height.json
# Fig 10: <v_x> against the frequency at n = 1.05, 1.75 and 2.8; h = 6 mm, a = 0.25, 60 mm, 30 s, 3 seeds.
have fig10-frequency || $B events-sweep $S $T --out $D/fig10-frequency --seeds 3 \
  --vary drive.frequency=15,17.5,20,22.5,25,27.5,30,32.5,35,37.5,40 \
  --vary particles.species.0.count=31,51,82 \
  --set box.width=0.06 --set base.tooth_height=0.006 --set base.asymmetry=0.25 \
  --set run.duration=30 --set run.transient=3 > $D/fig10-frequency.json
# Figs 8 and 9: <v_x> against the number of layers at three frequencies; 60 mm, 30 s, 3 seeds
# (the paper: 7 runs; 3 keep the whole script near an hour of one core).
for shape in "0.006 0.25 fig8-layers-h6" "0.003 0.1 fig9-layers-h3"; do
  set -- $shape
  have $3 || $B events-sweep $S $T --out $D/$3 --seeds 3 \
    --vary particles.species.0.count=$layers60 --vary drive.frequency=20,25,30 \
    --set box.width=0.06 --set base.tooth_height=$1 --set base.asymmetry=$2 \
    --set run.duration=30 --set run.transient=3 > $D/$3.json
done
# One run at n = 20 layers (584 disks) in the 60 mm cell, h = 6 mm, a = 0.25, 25 Hz, lid at 100 mm.
have layers-20 || $B events $S --force --quiet --out $D/layers-20 --set particles.species.0.count=584 \
  --set box.width=0.06 --set box.height=0.1 --set base.tooth_height=0.006 --set base.asymmetry=0.25 \
  --set drive.frequency=25 --set run.duration=30 --set run.transient=3 > $D/layers-20.json
# Fig 12: <v_x> against the frequency at n = 1.75 (51 disks), h = 6 mm, a = 0.25, 60 mm, 30 s,
# 7 seeds (as the paper's Fig 10 at this n), from below the layer's lift-off (Gamma = 1 at
# 11.1 Hz) to past the reversal.
have fig12-frequency || $B events-sweep $S $T --out $D/fig12-frequency --seeds 7 \
  --vary drive.frequency=10,11,12,12.5,13,13.5,14,14.5,15,16,17,18,19,20,22,24 \
  --set particles.species.0.count=51 \
  --set box.width=0.06 --set base.tooth_height=0.006 --set base.asymmetry=0.25 \
  --set run.duration=30 --set run.transient=3 > $D/fig12-frequency.json
# Figs 13-14: the momentum and mass density over one tooth per drive phase at the two
# reference points, 24 samples per period (4 per phase frame), 200 s each, seed 1.
have fields-positive || $B events $S --force --quiet --out $D/fields-positive --set base.tooth_height=0.003 \
  --set run.samples_per_period=24 --set run.duration=200 > $D/fields-positive.json
have fields-negative || $B events $S --force --quiet --out $D/fields-negative --set base.tooth_height=0.006 \
  --set base.asymmetry=0.25 --set drive.frequency=30 --set particles.species.0.count=25 \
  --set run.samples_per_period=24 --set run.duration=200 > $D/fields-negative.json
# Fig 12's onset on a finer grid: 12.8-14.2 Hz in steps of 0.1 Hz, 14 seeds of 30 s.
have fig12-onset || $B events-sweep $S $T --out $D/fig12-onset --seeds 14 \
  --vary drive.frequency=12.8,12.9,13,13.1,13.2,13.3,13.4,13.5,13.6,13.7,13.8,13.9,14,14.1,14.2 \
  --set particles.species.0.count=51 \
  --set box.width=0.06 --set base.tooth_height=0.006 --set base.asymmetry=0.25 \
  --set run.duration=30 --set run.transient=3 > $D/fig12-onset.json
# Fig 10 at n = 1.05 on a finer grid below the reversal (31 disks), 14 seeds of 30 s.
have fig10-n105-low || $B events-sweep $S $T --out $D/fig10-n105-low --seeds 14 \
  --vary drive.frequency=11,12,13,13.5,14,14.5,15,16,17 --set particles.species.0.count=31 \
  --set box.width=0.06 --set base.tooth_height=0.006 --set base.asymmetry=0.25 \
  --set run.duration=30 --set run.transient=3 > $D/fig10-n105-low.json
