#!/usr/bin/env python3
"""The plateau candidates' table: bulk T2/T1, the collision rates per species and H, per
candidate and Gamma, the mean over seeds and their spread (half the range). The rate of a
species is the inverse of its mean free time between collisions with grains, read from the
elastic column of the run's free_times.csv (an exponential with the run's mean free time tau:
rate(t) = exp(-t / tau) / tau, so tau follows from any two rows).
Usage: python3 scripts/mixture/plateau/table.py (writes docs/results/mixture/plateau/table.csv)."""
import csv, glob, json, math, os, re
from collections import defaultdict

# The study's folder (its runs and table.csv), from the repository root three folders up.
here = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', '..', 'docs', 'results', 'mixture', 'plateau')

def rates(path):
    rows = list(csv.DictReader(open(path)))
    out = []
    for k in ("1", "2"):
        t1, t2 = float(rows[0]["t_s"]), float(rows[-1]["t_s"])
        e1, e2 = float(rows[0][f"elastic_{k}_per_s"]), float(rows[-1][f"elastic_{k}_per_s"])
        out.append(math.log(e1 / e2) / (t2 - t1))
    return out

groups = defaultdict(list)
for path in sorted(glob.glob(os.path.join(here, "runs", "*.json"))):
    name, gamma, seed = re.match(r"(.+)-G(\d+)-s(\d+)\.json$", os.path.basename(path)).groups()
    s = json.load(open(path))
    r1, r2 = rates(path[:-5] + ".free_times.csv")
    groups[(name, int(gamma))].append({
        "ratio": s["temperature_ratio_bulk"], "rate_1": r1, "rate_2": r2,
        "reduced_height_mm": 1e3 * s["reduced_height_m"], "mean_height_mm": 1e3 * s["mean_height_m"],
        "collisions": s["collisions"], "cpu_s": s["cpu_s"], "ledger": s["energy_ledger_error"]})

keys = ["ratio", "rate_1", "rate_2", "reduced_height_mm", "mean_height_mm"]
with open(os.path.join(here, "table.csv"), "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["candidate", "gamma", "seeds"] + [x for k in keys for x in (k, k + "_spread")] + ["cpu_s", "worst_ledger"])
    for (name, gamma), runs in sorted(groups.items()):
        row = [name, gamma, len(runs)]
        for k in keys:
            v = [r[k] for r in runs]
            row += [f"{sum(v) / len(v):.5g}", f"{(max(v) - min(v)) / 2:.2g}"]
        row += [f"{sum(r['cpu_s'] for r in runs):.0f}", f"{max(r['ledger'] for r in runs):.1e}"]
        w.writerow(row)
        print(*row)
