#!/usr/bin/env bash
# A cheap probe of the rolling laws on the experiment's tray (issue 39's clump grid): 200
# grains (triangles of three spheres at d = R with the clump fit's radii, or the scene's
# spheres) on scenes/experiment.toml's tray and materials, started at rest at 3 Hz / 10 mm
# (no fluidising stage), 6 s, four frames per period, one thread; each case analysed, and
# its line printed: name, mobility (mean diameters moved per period in the tray's frame, the
# analyzer's), phase, the ledger's relative balance. About 20 s of one core per case.
#
#   scripts/experiment/rolling-probe.sh OUT tri NAME [--set KEY=VALUE ...]
#   scripts/experiment/rolling-probe.sh OUT sphere NAME [--set KEY=VALUE ...]
set -eu
out=$1 grain=$2 name=$3
shift 3
bin=${STRIPES:-target/release/stripes}
mkdir -p "$out"
scene="$out/probe-$grain.toml"
python3 - "$grain" "$scene" <<'PY'
import sys
grain, path = sys.argv[1], sys.argv[2]
src = open("scenes/experiment.toml").read()
a, b = src.index("[[drive.stages]]"), src.index("[particles]")
src = src[:a] + "[[drive.stages]]\nfrequency = 3.0\namplitude = 0.01\nduration = 100.0\n\n" + src[b:]
src = src.replace("count = 4848", "count = 200", 1)
src = src.replace("duration = 3602.0", "duration = 6.0", 1)
src = src.replace("snapshots_per_period = 1", "snapshots_per_period = 4", 1)
src = src.replace("threads = 0", "threads = 1", 1)
if grain == "tri":
    src = src.replace("radius_min = 0.882e-3", "radius_min = 0.616e-3", 1)
    src = src.replace("radius_max = 1.261e-3", "radius_max = 0.880e-3", 1)
    src = src.replace("[particles]\n", "[particles]\nshape = \"clump\"\nclump_spheres = 3\nclump_spacing = 1.0\n", 1)
elif grain != "sphere":
    sys.exit(f"grain: tri or sphere, not {grain}")
open(path, "w").write(src)
PY
nice "$bin" run "$scene" --out "$out/$name" --quiet --force "$@" > "$out/$name.json" 2> "$out/$name.err"
nice "$bin" analyze "$out/$name" --quiet --force > /dev/null 2>> "$out/$name.err"
python3 - "$out" "$name" <<'PY'
import json, sys
out, name = sys.argv[1], sys.argv[2]
a = json.load(open(f"{out}/{name}/analysis/summary.json"))
r = json.load(open(f"{out}/{name}.json"))
print(f"{name}\tmobility {a['mobility']:.4g}\tphase {a['phase']}\tledger {r['energy']['balance_relative']:.2g}")
PY
