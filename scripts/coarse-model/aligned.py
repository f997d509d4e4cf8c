#!/usr/bin/env python3
"""Excursion per half period against a grain's contacts along the shaking axis (issue 40, a
probe of what holds grains in bands): reads a DEM run's snapshots.bin (frames at the tray's
turning points, a drive A sin(2 pi f t)), and prints, before and after a time, the mean and
median excursion |dx| in the tray's frame per half period for grains with 0, 1, 2+ contacts
whose direction lies within 30 degrees of x ("aligned"), and likewise for contacts within 30
degrees of y ("side"); then by local packing (projected area within 2.5 mean diameters), and
the coherence: the spread of a grain's signed move less its neighbours' mean move.

    python3 scripts/coarse-model/aligned.py RUN F A SPLIT_S [GAP]

F, A: the drive's frequency (Hz) and amplitude (m); SPLIT_S: the time separating "before" from
"after" (e.g. the run's onset); GAP: contact when centres are nearer than (ri + rj)(1 + GAP)
(default 0.05, as `stripes mechanism`).
"""
import math
import sys

import numpy as np


def frames(path):
    raw = open(path, "rb").read()
    assert raw[:8] == b"STRPSNP1", "not a snapshot file"
    n = int(np.frombuffer(raw, "<u8", 1, 8)[0])
    length, width = np.frombuffer(raw, "<f8", 2, 16)
    radii = np.frombuffer(raw, "<f8", n, 32)
    head, size = 32 + 8 * n, 8 + 24 * n
    out = []
    for k in range((len(raw) - head) // size):
        at = head + k * size
        t = float(np.frombuffer(raw, "<f8", 1, at)[0])
        rec = np.frombuffer(raw, "<f4", 6 * n, at + 8).reshape(n, 6).astype(float)
        out.append((t, rec[:, 0].copy(), rec[:, 1].copy()))
    return length, width, radii, out


def contacts(x, y, r, length, gap):
    """Per grain: (aligned-with-x contacts, aligned-with-y contacts, all contacts, local
    packing: the projected area of the grains centred within 2.5 mean diameters over that
    disk, as `stripes mechanism`)."""
    n = len(x)
    reach = 2.5 * 2.0 * r.mean()
    cell = max(2.0 * r.max() * (1 + gap), reach)
    nx = max(1, int(length // cell))
    cx = np.floor((x % length) / length * nx).astype(int) % nx
    cy = np.floor(y / cell).astype(int)
    buckets = {}
    for i in range(n):
        buckets.setdefault((cx[i], cy[i]), []).append(i)
    ax = np.zeros(n, int)
    ay = np.zeros(n, int)
    al = np.zeros(n, int)
    pk = np.zeros(n)
    mates = [None] * n
    c30 = math.cos(math.radians(30))
    for (bx, by), members in buckets.items():
        near = []
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                near += buckets.get(((bx + dx) % nx, by + dy), [])
        near = np.array(near)
        for i in members:
            d_x = x[near] - x[i]
            d_x -= length * np.round(d_x / length)
            d_y = y[near] - y[i]
            d = np.hypot(d_x, d_y)
            pk[i] = (np.pi * r[near][d <= reach] ** 2).sum() / (np.pi * reach * reach)
            mates[i] = near[(d <= reach) & (near != i)]
            touch = (d < (r[i] + r[near]) * (1 + gap)) & (near != i)
            if touch.any():
                cosx = np.abs(d_x[touch]) / d[touch]
                ax[i] = int((cosx > c30).sum())
                ay[i] = int((cosx < 0.5).sum())
                al[i] = int(touch.sum())
    return ax, ay, al, pk, mates


def main():
    run, f, a, split = sys.argv[1], float(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4])
    gap = float(sys.argv[5]) if len(sys.argv) > 5 else 0.05
    length, width, r, fr = frames(f"{run}/snapshots.bin")
    period = 1.0 / f
    turning = [k for k, (t, _, _) in enumerate(fr) if abs(((t / period - 0.25) * 2) - round((t / period - 0.25) * 2)) < 1e-3]
    rows = {"before": [], "after": []}
    for p, q in zip(turning, turning[1:]):
        ta, xa, ya = fr[p]
        tb, xb, yb = fr[q]
        if abs((tb - ta) - 0.5 * period) > 1e-3 * period:
            continue
        tray = a * (math.sin(2 * math.pi * f * tb) - math.sin(2 * math.pi * f * ta))
        dx = (xb - xa) - tray
        dx -= length * np.round(dx / length)
        ax, ay, al, pk, mates = contacts(xa, ya, r, length, gap)
        # A grain's signed move less the mean move of the grains within 2.5 mean diameters.
        dev = np.array([dx[i] - dx[m].mean() if len(m) >= 3 else np.nan for i, m in enumerate(mates)])
        rows["before" if ta < split else "after"].append((np.abs(dx), ax, ay, al, pk, dev))
    for when, data in rows.items():
        if not data:
            continue
        ex = np.concatenate([d[0] for d in data]) * 1e3
        print(f"## {when} {split} s: {len(data)} half periods, {len(ex)} grain moves, excursion mean {ex.mean():.2f} mm, median {np.median(ex):.2f} mm")
        for name, idx in (("aligned (x)", 1), ("side (y)", 2), ("all", 3)):
            c = np.concatenate([d[idx] for d in data])
            parts = []
            for z in range(0, 4):
                m = (c == z) if z < 3 else (c >= 3)
                if m.sum():
                    parts.append(f"{z}{'+' if z == 3 else ''}: n {m.sum()} mean {ex[m].mean():.2f} median {np.median(ex[m]):.2f} frac<2mm {np.mean(ex[m] < 2):.2f}")
            print(f"  by {name} contacts: " + " | ".join(parts))
        pk = np.concatenate([d[4] for d in data])
        parts = []
        for lo in np.arange(0.1, 1.0, 0.1):
            m = (pk >= lo) & (pk < lo + 0.1)
            if m.sum() >= 20:
                parts.append(f"{lo:.1f}-{lo + 0.1:.1f}: n {m.sum()} mean {ex[m].mean():.2f} q10 {np.quantile(ex[m], 0.1):.2f}")
        print("  by local packing: " + " | ".join(parts))
        dev = np.concatenate([d[5] for d in data]) * 1e3
        parts = []
        for lo in np.arange(0.1, 1.0, 0.1):
            m = (pk >= lo) & (pk < lo + 0.1) & ~np.isnan(dev)
            if m.sum() >= 20:
                parts.append(f"{lo:.1f}-{lo + 0.1:.1f}: sd {dev[m].std():.2f}")
        print("  coherence, sd of (signed move - neighbours' mean move) (mm): " + " | ".join(parts))


if __name__ == "__main__":
    main()
