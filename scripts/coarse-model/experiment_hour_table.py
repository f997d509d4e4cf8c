#!/usr/bin/env python3
"""The camera count of the coarse model's hour runs at the experiment's times (issue 40):
per seed, the count at the strobe frame nearest 4 s (the experiment: about 12 stripes at
3-5 s), 100 s (9), 1400 s (5) and 3400 s (4), and the seeds' mean.

    python3 scripts/coarse-model/experiment_hour_table.py OUT SEED...
"""
import csv
import json
import sys

out, seeds = sys.argv[1], sys.argv[2:]
TIMES = [(4.0, 12), (100.0, 9), (1400.0, 5), (3400.0, 4)]
rows = []
for s in seeds:
    with open(f"{out}/seed{s}/analysis/camera_count.csv") as f:
        data = [(float(r["t"]), int(r["count"])) for r in csv.DictReader(f)]
    summary = json.load(open(f"{out}/seed{s}/analysis/summary.json"))
    counts = [min(data, key=lambda d: abs(d[0] - t))[1] for t, _ in TIMES]
    rows.append((s, summary.get("phase"), counts))
print("| seed | phase | " + " | ".join(f"count at {t:g} s (experiment {e})" for t, e in TIMES) + " |")
print("|" + "---|" * (2 + len(TIMES)))
for s, phase, counts in rows:
    print(f"| {s} | {phase} | " + " | ".join(str(c) for c in counts) + " |")
means = [sum(r[2][k] for r in rows) / len(rows) for k in range(len(TIMES))]
print("| mean | | " + " | ".join(f"{m:.1f}" for m in means) + " |")
