#!/usr/bin/env bash
# The experiment's fit grid (issue 39, step 5): mean mu_r x spread on the fit seed, each run the
# first 10 s at 3 Hz / 10 mm (scripts/experiment/fit.sh), then a table of the camera's numbers.
# Runs one at a time (one core); the held-out counts are never read.
#
#   scripts/experiment/fit-grid.sh OUT [extra KEY=VALUE ...]
#   MEANS="0.25 0.3" SPREADS="0.1" scripts/experiment/fit-grid.sh OUT
set -euo pipefail
out=$1
shift
means=${MEANS:-0.25 0.3 0.36 0.45}
spreads=${SPREADS:-0.1 0.2 0.3}
mkdir -p "$out"
for m in $means; do
  for s in $spreads; do
    dir="$out/mu$m-s$s-seed101"
    if [ -f "$dir.analysis.json" ]; then continue; fi
    start=$(date +%s)
    "$(dirname "$0")/fit.sh" "$out" "$m" "$s" 101 contact.rolling_damping=5e-3 "$@" || echo "$dir failed"
    echo "$dir wall_s $(( $(date +%s) - start ))" >> "$out/wall.txt"
  done
done
python3 - "$out" <<'PY'
import json, glob, os, sys
out = sys.argv[1]
rows = []
for a in sorted(glob.glob(os.path.join(out, "*.analysis.json"))):
    s = json.load(open(a))
    c = s.get("camera", {})
    name = os.path.basename(a).replace(".analysis.json", "")
    rows.append((name, s.get("phase"), s.get("contrast"), c.get("cluster_onset_s"), c.get("stripe_onset_s"),
                 c.get("stripe_count_first"), c.get("stripe_count_max"), c.get("stripe_count_last")))
print("| run | phase | contrast | cluster onset s | stripe onset s | count first | max | last |")
print("|---|---|---|---|---|---|---|---|")
for r in rows:
    print("| " + " | ".join("-" if v is None else (f"{v:.3g}" if isinstance(v, float) else str(v)) for v in r) + " |")
PY
