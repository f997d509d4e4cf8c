#!/usr/bin/env python3
"""The thesis-scale sweep (amplitude, packing, tray length) beside the five seeds of the
reference, all measured at the same time (6 s), and the laws fitted to them.

    python3 scripts/thesis-scale/sweep/collect.py RUNS_DIR > docs/results/thesis-scale/sweep/tables.md

RUNS_DIR holds one directory per run (NAME-sSEED, with `analysis/`); the reference seeds are
read from docs/results/thesis-scale/seed-*/structure.csv. Every run is measured on its own
frames up to 3 s, 4 s and 6 s (runs shorter than that time are left out of its
tables), so that runs of different lengths compare at one time. Writes runs.csv (at 3 s) and
the small files of each run into docs/results/thesis-scale/sweep/.
"""
import csv, json, math, os, shutil, statistics, sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..'))
from lsq import line_fit as fit  # noqa: E402

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', '..')
TS = os.path.join(ROOT, 'docs', 'results', 'thesis-scale')
HERE = os.path.join(TS, 'sweep')  # the study's folder: runs.csv and each run's small files
TIMES = (3.0, 4.0, 6.0)  # s: every run is measured on its frames up to each of these times
TAIL = 0.1           # the analysis' final tenth of the frames
PHI_J = 0.82         # the analysis' jammed packing of a band
G = 9.81

# The reference scene at the thesis' tray size, and what each sweep run changes.
REF = dict(length=0.4, count=8000, amplitude=0.010, frequency=3.0)
WIDTH, R_MIN, R_MAX = 0.02, 0.25e-3, 0.5e-3
TOP_VIEWS = ('A15',)  # top views are 3-4 MB each: kept for the run the report shows
MEAN_AREA = math.pi * (R_MIN ** 2 + R_MIN * R_MAX + R_MAX ** 2) / 3  # <pi r^2>, r uniform
CHANGES = {
    'A6': dict(amplitude=0.006), 'A15': dict(amplitude=0.015),
    'phi0.35': dict(count=6087), 'phi0.55': dict(count=9565),
    'L0.3': dict(length=0.3, count=6000), 'L0.5': dict(length=0.5, count=10000),
}


def packing(p):
    return p['count'] * MEAN_AREA / (p['length'] * WIDTH)


def late_frames(structure_csv, t_end):
    """S(k) peak spacing and in-band share, medians over the final tenth of the frames up to t_end."""
    rows = [r for r in csv.DictReader(open(structure_csv)) if float(r['t']) <= t_end + 1e-9]
    t_last = float(rows[-1]['t'])
    tail = [r for r in rows if float(r['t']) >= (1 - TAIL) * t_last]
    sp = statistics.median(float(r['spacing_m']) for r in tail)
    inb = statistics.median(float(r['in_band_fraction']) for r in tail)
    return sp, inb, t_last


def count_late(coarsening_csv, t_end):
    rows = [r for r in csv.DictReader(open(coarsening_csv)) if float(r['t']) <= t_end + 1e-9]
    t_last = float(rows[-1]['t'])
    return statistics.median(int(float(r['count'])) for r in rows if float(r['t']) >= (1 - TAIL) * t_last)


def gather(t_end, keep_files):
    """Every run that reaches t_end, measured on its frames up to t_end."""
    runs = []
    # The reference: the five seeds of the 100-period runs, cut at t_end.
    for s in range(1, 10):
        d = os.path.join(TS, f'seed-{s}')
        if not os.path.isdir(d):
            continue
        p = dict(REF)
        sp, inb, t = late_frames(os.path.join(d, 'structure.csv'), t_end)
        runs.append(dict(name='reference', seed=s, **p, packing=packing(p), spacing_frames=sp,
                         in_band_frames=inb, count_frames=count_late(os.path.join(d, 'coarsening.csv'), t_end),
                         phase='', spacing_analysis=float('nan'), band_width=float('nan'), contrast=float('nan'),
                         onset=float('nan'), t_end=t))
    for entry in sorted(os.listdir(SRC)):
        name, _, seed = entry.rpartition('-s')
        a = os.path.join(SRC, entry, 'analysis')
        if name not in CHANGES or not os.path.isfile(os.path.join(a, 'summary.json')):
            continue
        p = dict(REF, **CHANGES[name])
        summ = json.load(open(os.path.join(a, 'summary.json')))
        sp, inb, t = late_frames(os.path.join(a, 'structure.csv'), t_end)
        if t < 0.97 * t_end:
            continue
        nan = float('nan')
        runs.append(dict(name=name, seed=int(seed), **p, packing=packing(p), spacing_frames=sp, in_band_frames=inb,
                         count_frames=count_late(os.path.join(a, 'coarsening.csv'), t_end),
                         phase=summ['phase'] + ('' if summ.get('phase_robust') else '?'),
                         spacing_analysis=summ.get('spacing_m') or nan, band_width=summ.get('band_width_m') or nan,
                         contrast=summ.get('contrast') or nan, onset=summ.get('stripe_onset_s') or nan,
                         t_end=t, t_run=summ.get('t_end_s') or nan))
        if keep_files:
            keep = os.path.join(HERE, entry)
            os.makedirs(keep, exist_ok=True)
            for f in ('summary.json', 'structure.csv', 'coarsening.csv', 'bands_late.csv', 'phase_sensitivity.csv',
                      'top_view.png', 'density_map.png', 'structure_factor.png'):
                if f == 'top_view.png' and name not in TOP_VIEWS:
                    continue
                if os.path.isfile(os.path.join(a, f)):
                    shutil.copy(os.path.join(a, f), keep)
            for f in ('summary.json', 'scene.toml', 'config.json'):
                if os.path.isfile(os.path.join(SRC, entry, f)):
                    shutil.copy(os.path.join(SRC, entry, f), os.path.join(keep, 'run_' + f if f == 'summary.json' else f))
    return runs


SRC = sys.argv[1]
runs = gather(TIMES[0], True)
cols = ['name', 'seed', 'length', 'count', 'amplitude', 'frequency', 'packing', 'phase', 'spacing_frames',
        'spacing_analysis', 'in_band_frames', 'count_frames', 'band_width', 'contrast', 'onset', 't_end', 't_run']
with open(os.path.join(HERE, 'runs.csv'), 'w', newline='') as f:
    w = csv.DictWriter(f, cols, extrasaction='ignore')
    w.writeheader()
    for r in runs:
        w.writerow(r)


def mse(xs):
    m = sum(xs) / len(xs)
    se = math.sqrt(sum((x - m) ** 2 for x in xs) / (len(xs) - 1) / len(xs)) if len(xs) > 1 else float('nan')
    return m, se


def f1(x, scale=1e3, d=1):
    return '-' if x != x else f'{x * scale:.{d}f}'






def tables(runs, t_end):
    print(f'\n### Every run at {t_end:g} s (S(k) peak and in-band share: medians over the last tenth of the frames)\n')
    print('| run | seed | L (m) | grains | A (mm) | packing | Gamma | phase (whole run) | S(k) spacing (mm) | L / spacing | in bands | bands | band width (mm), whole run | onset (s) |')
    print('|---|---|---|---|---|---|---|---|---|---|---|---|---|---|')
    for r in runs:
        gam = r['amplitude'] * (2 * math.pi * r['frequency']) ** 2 / G
        print(f"| {r['name']} | {r['seed']} | {r['length']:.1f} | {r['count']} | {r['amplitude'] * 1e3:.0f} | {r['packing']:.3f} | "
              f"{gam:.2f} | {r['phase'] or '(100-period run)'} | {f1(r['spacing_frames'])} | {r['length'] / r['spacing_frames']:.1f} | "
              f"{r['in_band_frames']:.2f} | {r['count_frames']} | {f1(r['band_width'])} | {f1(r['onset'], 1, 2)} |")

    print('\n### By setting (mean +- standard error over seeds)\n')
    print('| setting | runs | S(k) spacing (mm) | in bands | prediction (15/7) A / (1 - phi / 0.82) (mm) | spacing / prediction |')
    print('|---|---|---|---|---|---|')
    groups = {}
    for r in runs:
        groups.setdefault(r['name'], []).append(r)
    for name, rs in groups.items():
        sp = mse([r['spacing_frames'] for r in rs])
        ib = mse([r['in_band_frames'] for r in rs])
        pred = 15 / 7 * rs[0]['amplitude'] / (1 - rs[0]['packing'] / PHI_J)
        se = '' if sp[1] != sp[1] else f' +- {sp[1] * 1e3:.1f}'
        print(f"| {name} | {len(rs)} | {sp[0] * 1e3:.1f}{se} | {ib[0]:.2f} | {pred * 1e3:.1f} | {sp[0] / pred:.2f} |")




def laws(runs, t_end, label):
    print(f'\n### Laws fitted at {t_end:g} s, {label}\n')
    # Amplitude at the reference packing and tray: spacing = c A^b.
    amp = [r for r in runs if r['name'] in ('reference', 'A6', 'A15')]
    if len({r['amplitude'] for r in amp}) >= 2:
        b, sb, c, sc, _ = fit([math.log(r['amplitude']) for r in amp], [math.log(r['spacing_frames']) for r in amp])
        print(f'- Amplitude (packing 0.46, 0.4 m, {len(amp)} runs): spacing ~ A^b with **b = {b:.2f} +- {sb:.2f}** '
              f'(the excursion prediction: b = 1).')
    # Packing at the reference amplitude and tray: spacing against 1 / (1 - phi / phi_j).
    pk = [r for r in runs if r['name'] in ('reference', 'phi0.35', 'phi0.55')]
    if len({r['count'] for r in pk}) >= 2:
        b, sb, c, sc, _ = fit([math.log(1 / (1 - r['packing'] / PHI_J)) for r in pk], [math.log(r['spacing_frames']) for r in pk])
        print(f'- Packing (A = 10 mm, 0.4 m, {len(pk)} runs): spacing ~ (1 / (1 - phi / 0.82))^b with **b = {b:.2f} +- {sb:.2f}** '
              f'(the prediction: b = 1).')
    # Tray length at the reference drive and packing: spacing ~ L^b (b = 0 if the box does not set it).
    tl = [r for r in runs if r['name'] in ('reference', 'L0.3', 'L0.5')]
    if len({r['length'] for r in tl}) >= 2:
        b, sb, c, sc, _ = fit([math.log(r['length']) for r in tl], [math.log(r['spacing_frames']) for r in tl])
        print(f'- Tray length (A = 10 mm, packing 0.46, {len(tl)} runs): spacing ~ L^b with **b = {b:.2f} +- {sb:.2f}** '
              f'(0 if the box does not set the spacing).')
    # The prediction's one constant over every run at 0.4 m: spacing = k A / (1 - phi / phi_j).
    all4 = [r for r in runs if r['length'] == 0.4]
    k = [r['spacing_frames'] / (r['amplitude'] / (1 - r['packing'] / PHI_J)) for r in all4]
    m, se = mse(k)
    print(f'- One constant over the {len(all4)} runs on 0.4 m: spacing = k A / (1 - phi / 0.82), **k = {m:.2f} +- {se:.2f}** '
          f'(the prediction: 15/7 = {15 / 7:.2f}); spread of k between runs {statistics.stdev(k):.2f}.')


MIN_IN_BANDS = 0.2  # a run whose bands hold fewer grains has no settled spacing to fit


for t_end in TIMES:
    rs = gather(t_end, False)
    tables(rs, t_end)
    laws(rs, t_end, 'every run')
    banded = [r for r in rs if r['in_band_frames'] >= MIN_IN_BANDS]
    left = sorted({r['name'] for r in rs} - {r['name'] for r in banded})
    laws(banded, t_end, f'runs with at least {MIN_IN_BANDS:g} of the grains in bands'
         + (f' (leaves out {", ".join(left)})' if left else ''))
