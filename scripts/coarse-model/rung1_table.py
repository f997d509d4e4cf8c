#!/usr/bin/env python3
"""The rung-1 table (issue 40): per seed, the DEM's and the automaton's onset, band width,
share of grains in bands and mobility (one-period mean squared displacement, `stripes
analyze`'s `mobility`), then whether each automaton value lies within the DEM's seed range.

    python3 scripts/coarse-model/rung1_table.py DEM OUT RULE SEED...
"""
import json
import sys

dem, out, rule, seeds = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
KEYS = [("stripe_onset_s", "onset s", 1.0), ("band_width_m", "band width mm", 1e3),
        ("in_band_fraction", "in bands", 1.0), ("mobility", "mobility", 1.0),
        ("spacing_m", "S(k) spacing mm", 1e3)]


def row(s):
    return [s.get(k) for k, _, _ in KEYS] + [s.get("phase"), s.get("stripe_count_final"), s.get("t_end_s")]


def fmt(v, scale):
    return "-" if v is None else f"{v * scale:.3g}"


rows = []
for s in seeds:
    d = json.load(open(f"{dem}/seed{s}/analysis-rung1/summary.json"))
    a = json.load(open(f"{out}/{rule}-seed{s}/analysis/summary.json"))
    rows.append((s, row(d), row(a)))
head = "| run | phase | stripes at end | " + " | ".join(name for _, name, _ in KEYS) + " |"
print(head)
print("|" + "---|" * (3 + len(KEYS)))
for who, idx in (("DEM", 1), (f"automaton ({rule})", 2)):
    for s, d, a in rows:
        r = (d, a)[idx - 1]
        print(f"| {who} seed {s} | {r[-3]} | {r[-2]} | " + " | ".join(fmt(v, sc) for v, (_, _, sc) in zip(r, KEYS)) + " |")
print()
for k, (key, name, sc) in enumerate(KEYS):
    dv = [d[k] for _, d, _ in rows if d[k] is not None]
    av = [a[k] for _, _, a in rows]
    if not dv:
        print(f"- {name}: the DEM gives none")
        continue
    lo, hi = min(dv), max(dv)
    inside = sum(1 for v in av if v is not None and lo <= v <= hi)
    vals = ", ".join(fmt(v, sc) for v in av)
    verdict = "met" if inside == len(av) else "missed"
    print(f"- {name}: DEM {fmt(lo, sc)}-{fmt(hi, sc)}; automaton {vals}: {inside} of {len(av)} inside, **{verdict}**")
