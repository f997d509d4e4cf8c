#!/usr/bin/env bash
# The clump fit run of issue 39, step 3: the experiment scene with triangles of three spheres
# (spacing d = R, radii 0.616-0.880 mm: a triangle's top view is a seed's disc), fit seed 101,
# 12 s (2 s at 5 Hz / 20 mm, then the first 10 s at 3 Hz / 10 mm), four frames per period,
# a checkpoint every 0.5 simulated s; the scene's own laws otherwise (docs/results/experiment/
# study.md, "Clumps"). Then the early targets only:
#   stripes analyze OUT --force --top-view 2.05,4,6,8,12 && python3 scripts/experiment/early.py OUT
#
#   scripts/experiment/clumps-fit.sh OUT            # from the start
#   scripts/experiment/clumps-fit.sh OUT --resume   # on from OUT's checkpoint
#   scripts/experiment/clumps-fit.sh OUT --set contact.wall_friction=0.45   # other values
#
# The shape and size come from the environment (defaults: the first run's triangles):
#   CLUMP_SPHERES (3), CLUMP_SPACING (1.0, d / R), RADIUS_MIN (0.616e-3), RADIUS_MAX (0.880e-3).
# Dimers of the seeds' projected area at d = R: CLUMP_SPHERES=2 RADIUS_MIN=0.695e-3
# RADIUS_MAX=0.994e-3 (two discs at d = R cover 5.055 r^2; a seed's disc is pi r_seed^2, so
# r = 0.7883 r_seed for r_seed = 0.882-1.261 mm).
#
# To go on from the checkpoint committed in docs/results/experiment/clumps-fit/ on another
# machine: copy its scene.toml and checkpoint.bin into OUT, put the committed
# snapshots-header.bin there as snapshots.bin, sparse to 1 GB (`truncate -s 1G`; the frames
# before the checkpoint are then zeros), and a thermo.csv holding thermo-header.csv's line;
# then run with --resume. The checkpoint is before t3 = 2 s, so every frame the early
# targets read (from t3 on) is written by the continuation.
set -u
out=$1
shift
bin=${STRIPES:-target/release/stripes}
nice "$bin" run scenes/experiment.toml --out "$out" --quiet "$@" \
  --set run.duration=12 --set run.seed=101 --set run.threads=1 --set run.snapshots_per_period=4 \
  --set run.checkpoint_interval=0.5 \
  --set particles.shape=clump --set particles.clump_spheres="${CLUMP_SPHERES:-3}" \
  --set particles.clump_spacing="${CLUMP_SPACING:-1.0}" \
  --set particles.radius_min="${RADIUS_MIN:-0.616e-3}" --set particles.radius_max="${RADIUS_MAX:-0.880e-3}"
