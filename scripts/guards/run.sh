#!/bin/bash
# What each collapse guard costs (the table in docs/scenes.md, under the event-driven scenes):
# scenes/mixture.toml for 10 s after a 2 s transient, seeds 1 and 2, with its velocity-dependent
# restitution and with a constant one under each guard. The rows and the runs are defined in
# tests/guard_table.rs; this reruns them (about a minute of CPU), stores each run's numbers in
# docs/results/guards/<row>-s<seed>.json and rewrites the table from them. The test
# `the_guard_table_in_scenes_md_is_the_stored_runs` (in .ci/run) then checks the table
# against the stored runs.
# Usage: bash scripts/guards/run.sh (from the repository root).
set -euo pipefail
STRIPES_WRITE_GUARD_TABLE=1 cargo test --release -p stripes --test guard_table -- --ignored --exact rerun_the_guard_runs
