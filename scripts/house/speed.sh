#!/usr/bin/env bash
# Issue 42's "speed is unchanged": two binaries side by side in one run, alternating, on the
# stripe scene (one thread, a cached sample, 0.3 s), five times each; prints each run's
# particle-steps per second and the median ratio NEW / OLD.
#   scripts/house/speed.sh OLD_BINARY NEW_BINARY [OUT]
set -eu
old=$1 new=$2 out=${3:-/tmp/stripes-house-speed}
mkdir -p "$out"
rate() {
    "$1" run scenes/stripes.toml --quiet --force --out "$out/run" --sample-cache "$out/samples" \
        --set run.duration=0.3 --set run.threads=1 2>/dev/null | tail -1 |
        python3 -c 'import json,sys; print(json.load(sys.stdin)["particle_steps_per_s"])'
}
rate "$new" > /dev/null   # the sample, prepared once, outside the timing
: > "$out/rates"
for k in 1 2 3 4 5; do
    echo "old $(rate "$old")" >> "$out/rates"
    echo "new $(rate "$new")" >> "$out/rates"
done
cat "$out/rates"
python3 - "$out/rates" <<'PY'
import statistics, sys
r = {"old": [], "new": []}
for line in open(sys.argv[1]):
    k, v = line.split()
    r[k].append(float(v))
ratios = [n / o for n, o in zip(r["new"], r["old"])]
print(f"new/old per pair: {', '.join(f'{x:.3f}' for x in ratios)}; median {statistics.median(ratios):.3f}")
PY
