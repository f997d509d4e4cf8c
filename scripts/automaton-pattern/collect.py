#!/usr/bin/env python3
"""Writes the study's small CSVs into docs/results/automaton-pattern/.

    RUNS=/work/runs/autopattern python3 scripts/automaton-pattern/collect.py CHOSEN_GAMMA_C
"""
import csv, json, math, os, sys
# The study's runs (phase maps pm/, fit scan fit/, held-out seeds held/): not committed.
R = os.environ.get('RUNS', '/work/runs/autopattern')
ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..')
OUT = os.path.join(ROOT, 'docs', 'results', 'automaton-pattern')
DEM_MAP = os.path.join(ROOT, 'docs', 'results', 'phase-map-stripes', 'phase_map_dem.csv')
OLD_MAP = os.path.join(ROOT, 'docs', 'results', 'phase-map-stripes', 'phase_map_automaton_6s.csv')
chosen = sys.argv[1]

def load(p):
    return {(float(r['frequency']), float(r['amplitude']), int(r['sample'])): r['phase'] for r in csv.DictReader(open(p))}
dem = load(DEM_MAP)
def trivial(f, a):
    g = a * (2 * math.pi * f) ** 2 / 9.81
    if abs(a - 0.002) < 1e-9: return 'nothing'
    return 'stripes' if g < 2.45 else 'gas'
sets = [('fit', lambda f, s: f in (3, 5, 10) and s == 0),
        ('held_out', lambda f, s: f in (4, 7, 20)),
        ('seed2_of_fit_cells', lambda f, s: f in (3, 5, 10) and s == 1),
        ('all', lambda f, s: True)]
def score(m):
    out = {}
    for name, sel in sets:
        keys = [k for k in dem if sel(k[0], k[2])]
        out[name] = sum(m.get(k) == dem[k] for k in keys)
        out[name + '_n'] = len(keys)
    return out
rows = []
triv = {k: trivial(k[0], k[1]) for k in dem}
rows.append(dict(rule='trivial (nothing at 2 mm, stripes below Gamma 2.45, else gas)', gamma_c='', **score(triv)))
rows.append(dict(rule='old automaton (scene table, committed 6 s map)', gamma_c='', **score(load(OLD_MAP))))
rows.append(dict(rule='graded, no melt', gamma_c='', **score(load(f'{R}/pm/a08-nomelt/phase_map.csv'))))
for g in ['0.6', '0.8', '1.0', '1.1', '1.2', '1.3', '1.5', '2.0']:
    p = f'{R}/pm/a08-m{g}/phase_map.csv'
    if os.path.exists(p):
        rows.append(dict(rule='graded, melt', gamma_c=g, **score(load(p))))
with open(f'{OUT}/phase_agreement.csv', 'w', newline='') as f:
    w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
    w.writeheader(); w.writerows(rows)
# the chosen map, with the DEM's and the trivial rule's phase beside it
with open(f'{R}/pm/a08-m{chosen}/phase_map.csv') as f, open(f'{OUT}/phase_map_graded.csv', 'w', newline='') as g:
    rd = csv.DictReader(f)
    w = csv.DictWriter(g, fieldnames=rd.fieldnames + ['gamma', 'split', 'dem_phase', 'trivial_phase'])
    w.writeheader()
    for r in rd:
        k = (float(r['frequency']), float(r['amplitude']), int(r['sample']))
        split = 'fit' if k[0] in (3, 5, 10) and k[2] == 0 else ('held_out' if k[0] in (4, 7, 20) else 'seed2_of_fit_cells')
        r.update(gamma='%.3f' % (k[1] * (2 * math.pi * k[0]) ** 2 / 9.81), split=split, dem_phase=dem[k], trivial_phase=trivial(k[0], k[1]))
        w.writerow(r)
# structure: fit scan (seed 1) and held-out seeds
keys = ['spacing_m', 'band_width_m', 'in_band_fraction', 'contrast', 'stripe_onset_s']
def struct_row(path, **extra):
    d = json.load(open(f'{path}/summary.json'))
    D, A = d['dem']['analysis'], d['automaton']['analysis']
    row = dict(extra)
    row['pattern_distance'] = d['pattern_distance']
    row['seed_scale'] = d['pattern_distance_seed_scale']
    row['phase'] = A['phase']
    row['stripes_final'] = A['stripe_count_final']
    for k in keys:
        row['automaton_' + k] = A[k]
        row['dem_' + k] = D[k]
    return row
fit = []
for sl in ['in-bands', 'before-bands']:
    for a in ['0.75', '0.8', '0.85', '0.9', '0.95', '1.0']:
        fit.append(struct_row(f'{R}/fit/{sl}-a{a}', slope=sl, activation=a, seed=1))
with open(f'{OUT}/structure_fit_seed1.csv', 'w', newline='') as f:
    w = csv.DictWriter(f, fieldnames=list(fit[0].keys())); w.writeheader(); w.writerows(fit)
held = []
for rule in ['graded', 'old']:
    for s, scale in [(1, 2), (2, 3), (3, 2)]:
        held.append(struct_row(f'{R}/held/{rule}-s{s}', rule=rule, seed=s, seed_scale_run=scale, split='fit' if s == 1 else 'held_out'))
with open(f'{OUT}/structure_by_seed.csv', 'w', newline='') as f:
    w = csv.DictWriter(f, fieldnames=list(held[0].keys())); w.writeheader(); w.writerows(held)
for r in rows: print(r)
for r in held: print({k: (round(v, 4) if isinstance(v, float) else v) for k, v in r.items()})
