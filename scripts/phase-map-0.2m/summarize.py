#!/usr/bin/env python3
"""Markdown tables of the 0.2 m phase map from runs.csv (written by collect.py).

    python3 scripts/phase-map-0.2m/summarize.py docs/results/phase-map-0.2m/runs.csv
"""
import csv, math, os, sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..'))
from lsq import line_fit  # noqa: E402
from collections import defaultdict

rows = list(csv.DictReader(open(sys.argv[1])))
PHI, PHI_J = 0.458, 0.82  # the tray's packing; the analysis' jammed packing of a band


def num(x):
    return float(x) if x not in ('', None) else float('nan')


def fmt(x, scale=1.0, d=0):
    return '-' if x != x else f'{x * scale:.{d}f}'


freqs = sorted({num(r['frequency_hz']) for r in rows})
amps = sorted({num(r['amplitude_m']) for r in rows})
cells = defaultdict(dict)  # (model, f, A) -> sample -> row
for r in rows:
    cells[(r['model'], num(r['frequency_hz']), num(r['amplitude_m']))][int(r['sample'])] = r

short = {'stripes': 'S', 'gas': 'g', 'nothing': 'N'}
for model in ('dem', 'automaton'):
    if not any(k[0] == model for k in cells):
        continue
    print(f'\n### {model}: phase per sample (seed 1 / seed 2), stripe count, S(k) spacing (mm)\n')
    print('| A (mm) \\ nu (Hz) | ' + ' | '.join(f'{f:.2f}' for f in freqs) + ' |')
    print('|---' * (len(freqs) + 1) + '|')
    for a in reversed(amps):
        out = []
        for f in freqs:
            c = cells.get((model, f, a), {})
            if not c:
                out.append('(not run)')
                continue
            g = a * (2 * math.pi * f) ** 2 / 9.81
            parts = []
            for s in sorted(c):
                r = c[s]
                mark = short[r['phase']] + ('' if r['phase_robust'] == 'True' else '?')
                parts.append(f"{mark} {r['stationary_stripe_count']}, {fmt(num(r['spacing_m']), 1e3)}")
            out.append(' / '.join(parts) + f' (G {g:.2f})')
        print(f'| {a * 1e3:.2f} | ' + ' | '.join(out) + ' |')

# Spacing against the amplitude: runs the analyzer calls stripes, by amplitude.
print('\n### Spacing against the amplitude (DEM runs classified stripes)\n')
print('| A (mm) | runs | S(k) spacing (mm), mean +- s.e. | L / count (mm) | band width (mm) | in bands | onset (s) | predicted (15/7) A / (1 - phi/phi_j) (mm) |')
print('|---|---|---|---|---|---|---|---|')
pts = []
for a in amps:
    sel = [r for r in rows if r['model'] == 'dem' and num(r['amplitude_m']) == a and r['phase'] == 'stripes']
    sp = [num(r['spacing_m']) for r in sel if num(r['spacing_m']) == num(r['spacing_m'])]
    cnt = [0.2 / int(r['stationary_stripe_count']) for r in sel if int(r['stationary_stripe_count']) > 0]
    wid = [num(r['band_width_m']) for r in sel if num(r['band_width_m']) == num(r['band_width_m'])]
    inb = [num(r['in_band_fraction']) for r in sel]
    ons = [num(r['stripe_onset_s']) for r in sel if num(r['stripe_onset_s']) == num(r['stripe_onset_s'])]
    pred = 15 / 7 * a / (1 - PHI / PHI_J)

    def ms(xs, scale=1e3):
        if not xs:
            return '-'
        m = sum(xs) / len(xs)
        if len(xs) < 2:
            return f'{m * scale:.{2 if scale == 1 else 1}f}'
        se = math.sqrt(sum((x - m) ** 2 for x in xs) / (len(xs) - 1) / len(xs))
        d = 2 if scale == 1 else 1
        return f'{m * scale:.{d}f} +- {se * scale:.{d}f}'
    print(f'| {a * 1e3:.2f} | {len(sel)} | {ms(sp)} | {ms(cnt)} | {ms(wid)} | {ms(inb, 1)} | {ms(ons, 1)} | {pred * 1e3:.1f} |')
    pts += [(a, x) for x in sp]

# Power law spacing = c A^b, least squares in logs, with the standard error of b.
if len({p[0] for p in pts}) >= 2:
    xs = [math.log(a) for a, _ in pts]
    ys = [math.log(s) for _, s in pts]
    n = len(xs)
    b, se_b, c, _, _ = line_fit(xs, ys)
    print(f'\nPower law over {n} runs: spacing = {math.exp(c) * 1e3:.3g} mm x (A / 1 m)^b, '
          f'**b = {b:.2f} +- {se_b:.2f}** (the prediction: b = 1).')
    # The prediction's form (spacing proportional to A): ratio spacing / A, mean and s.e.
    r = [s / a for a, s in pts]
    m = sum(r) / len(r)
    se = math.sqrt(sum((x - m) ** 2 for x in r) / (len(r) - 1) / len(r)) if len(r) > 1 else float('nan')
    print(f'Spacing / A = {m:.2f} +- {se:.2f} (prediction {15 / 7 / (1 - PHI / PHI_J):.2f}).')

# The two models cell by cell and sample by sample, and the trivial rule.
pairs = [(k, s) for k in cells if k[0] == 'dem' for s in cells[k]]
both = [(k, s) for k, s in pairs if s in cells.get(('automaton', k[1], k[2]), {})]
if both:
    def trivial(f, a):
        return 'stripes' if a * (2 * math.pi * f) ** 2 / 9.81 < 2.45 else 'gas'
    agree = sum(cells[k][s]['phase'] == cells[('automaton', k[1], k[2])][s]['phase'] for k, s in both)
    triv = sum(cells[k][s]['phase'] == trivial(k[1], k[2]) for k, s in both)
    print(f'\nSample by sample over {len(both)} DEM runs: the automaton agrees on {agree}, '
          f'the trivial rule (stripes below Gamma 2.45, else gas) on {triv}.')

# Where the DEM's stripes give way to a gas: the largest drive of a stripes run and the
# smallest of a gas run, in Gamma and in peak tray speed 2 pi f A.
dem = [r for r in rows if r['model'] == 'dem' and r['phase'] in ('stripes', 'gas')]
for name, fn in (('Gamma', lambda r: num(r['gamma'])),
                 ('peak speed (m/s)', lambda r: 2 * math.pi * num(r['frequency_hz']) * num(r['amplitude_m']))):
    st = [fn(r) for r in dem if r['phase'] == 'stripes']
    ga = [fn(r) for r in dem if r['phase'] == 'gas' and num(r['amplitude_m']) > 0.006]
    if st and ga:
        print(f'\n{name}: DEM stripes up to {max(st):.2f}, gas (A > 6 mm) from {min(ga):.2f}'
              + (' (separated)' if max(st) < min(ga) else ' (overlapping)'))
