#!/usr/bin/env python3
"""Per-run structure of the 0.2 m phase map, from a finished sweep directory.

    python3 scripts/phase-map-0.2m/collect.py SWEEP_DIR > docs/results/phase-map-0.2m/runs.csv

Reads jobs/<id>/result.json and jobs/<id>/analysis/summary.json; one row per run.
"""
import csv, glob, json, math, os, sys

sweep = sys.argv[1]
cols = ['model', 'frequency_hz', 'amplitude_m', 'gamma', 'sample', 'seed', 'phase', 'phase_robust',
        'votes_stripes', 'votes_gas', 'votes_nothing', 'stripe_count_final', 'stationary_stripe_count',
        'spacing_m', 'band_width_m', 'band_gap_m', 'in_band_fraction', 'stripe_onset_s', 'contrast',
        'mobility', 'structure_peak_height', 'structure_peak_width_per_m', 'frames', 't_end_s', 'wall_s', 'particle_steps_per_s']
w = csv.writer(sys.stdout)
w.writerow(cols)
rows = []
for res in sorted(glob.glob(os.path.join(sweep, 'jobs', '*', 'result.json'))):
    r = json.load(open(res))
    a = json.load(open(os.path.join(os.path.dirname(res), 'analysis', 'summary.json')))
    f, amp = float(r['frequency']), float(r['amplitude'])
    job = os.path.basename(os.path.dirname(res))
    v = a.get('phase_votes') or {}
    seed = 1 + int(r['sample'])  # run.seed + sample (the scene's run.seed is 1)
    row = [job.split('-')[0], f, amp, amp * (2 * math.pi * f) ** 2 / 9.81, r.get('sample', job.rsplit('-s', 1)[1]),
           seed, a['phase'], a['phase_robust'], v.get('stripes'), v.get('gas'), v.get('nothing'),
           a['stripe_count_final'], a['stationary_stripe_count'], a['spacing_m'], a['band_width_m'],
           a['band_gap_m'], a['in_band_fraction'], a['stripe_onset_s'], a['contrast'], a['mobility'],
           a['structure_peak_height'], a['structure_peak_width_per_m'], a['frames'], a['t_end_s'], r['speed']['wall_s'], r['speed']['particle_steps_per_s']]
    rows.append(row)
rows.sort(key=lambda x: (x[0], x[1], x[2], int(x[4])))
for row in rows:
    w.writerow(['' if x is None else x for x in row])
