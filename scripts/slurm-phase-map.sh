#!/usr/bin/env bash
# A (nu, A) phase map as a Slurm job array: one array task per shard, all writing into one
# shared sweep directory; each job's result.json is written atomically and finished jobs are
# skipped, so a resubmitted array redoes only what is missing. Merge with `stripes collect`.
#
#   sbatch --array=0-15 scripts/slurm-phase-map.sh scenes/thesis-reference.toml /shared/phase-map
#   # when the array is done (or at any time, for a partial map):
#   stripes collect /shared/phase-map
#
#SBATCH --job-name=stripes-phase-map
#SBATCH --cpus-per-task=2
#SBATCH --time=24:00:00
#SBATCH --output=slurm-%A_%a.out
set -euo pipefail
SCENE=${1:?scene file}
OUT=${2:?shared sweep directory}
SHARDS=${SLURM_ARRAY_TASK_COUNT:?run as a job array: sbatch --array=0-N}
stripes phase-map "$SCENE" \
  --frequency "${FREQUENCY:-5:29:7}" --amplitude "${AMPLITUDE:-0.005:0.04:8}" \
  --model "${MODEL:-both}" --seeds "${SAMPLES:-1}" \
  --out "$OUT" --sample-cache "$OUT/samples" \
  --shard "${SLURM_ARRAY_TASK_ID}/${SHARDS}" --jobs "${SLURM_CPUS_PER_TASK:-1}" --quiet
