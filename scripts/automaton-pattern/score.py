#!/usr/bin/env python3
"""Per-sample phase agreement of an automaton phase map with the DEM's committed map.
Fit: f in {3,5,10} Hz, sample 0 (seed 1). Held-out: f in {4,7,20} Hz, both samples.
Also: f in {3,5,10}, sample 1 (unseen seed of fitted cells)."""
import csv, sys, math
dem = {}
for r in csv.DictReader(open(sys.argv[1])):
    dem[(float(r['frequency']), float(r['amplitude']), int(r['sample']))] = r['phase']
aut = {}
for r in csv.DictReader(open(sys.argv[2])):
    aut[(float(r['frequency']), float(r['amplitude']), int(r['sample']))] = r['phase']
def trivial(f, a):
    g = a * (2 * math.pi * f) ** 2 / 9.81
    if abs(a - 0.002) < 1e-9: return 'nothing'
    return 'stripes' if g < 2.45 else 'gas'
sets = {
  'fit (3,5,10 Hz; seed 1)': lambda f, s: f in (3, 5, 10) and s == 0,
  'held-out (4,7,20 Hz; seeds 1,2)': lambda f, s: f in (4, 7, 20),
  'seed 2 of fitted cells': lambda f, s: f in (3, 5, 10) and s == 1,
  'all 72': lambda f, s: True,
}
for name, sel in sets.items():
    keys = [k for k in dem if sel(k[0], k[2])]
    a = sum(aut.get(k) == dem[k] for k in keys)
    t = sum(trivial(k[0], k[1]) == dem[k] for k in keys)
    print(f"{name}: automaton {a}/{len(keys)}, trivial {t}/{len(keys)}")
if len(sys.argv) > 3:
    for k in sorted(dem):
        if aut.get(k) != dem[k]:
            print('  differs', k, 'dem', dem[k], 'aut', aut.get(k), 'trivial', trivial(k[0], k[1]))
