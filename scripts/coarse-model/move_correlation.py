#!/usr/bin/env python3
"""How far across the tray grains move together (issue 40): on a DEM run's frames at the
tray's turning points, the correlation of two grains' moves per half period (in the tray's
frame, less the half period's mean move of all grains) against their separation across
the tray |dy|, for pairs whose separation along x is within 2.5 mean diameters (the local
disk's radius), and against |dx| for pairs within 2.5 mean diameters across.

    python3 scripts/coarse-model/move_correlation.py RUN F A [FROM_S [TO_S]]

F, A: the drive's frequency (Hz) and amplitude (m); FROM_S, TO_S: only half periods starting
in this window (default: all).
"""
import math
import sys

import numpy as np

sys.path.insert(0, __file__.rsplit("/", 1)[0])
from aligned import frames  # noqa: E402


def main():
    run, f, a = sys.argv[1], float(sys.argv[2]), float(sys.argv[3])
    start = float(sys.argv[4]) if len(sys.argv) > 4 else 0.0
    end = float(sys.argv[5]) if len(sys.argv) > 5 else math.inf
    length, width, r, fr = frames(f"{run}/snapshots.bin")
    d = 2.0 * r.mean()
    reach = 2.5 * d
    period = 1.0 / f
    turning = [k for k, (t, _, _) in enumerate(fr) if abs(((t / period - 0.25) * 2) - round((t / period - 0.25) * 2)) < 1e-3]
    bins_y = np.arange(0.0, width + d, d)
    bins_x = np.arange(0.0, 0.5 * length, d)
    sy = np.zeros(len(bins_y)); ny = np.zeros(len(bins_y))
    sx = np.zeros(len(bins_x)); nx = np.zeros(len(bins_x))
    var, nv, halves = 0.0, 0, 0
    for p, q in zip(turning, turning[1:]):
        ta, xa, ya = fr[p]
        tb, xb, _ = fr[q]
        if ta < start or ta >= end or abs((tb - ta) - 0.5 * period) > 1e-3 * period:
            continue
        halves += 1
        tray = a * (math.sin(2 * math.pi * f * tb) - math.sin(2 * math.pi * f * ta))
        dx = (xb - xa) - tray
        dx -= length * np.round(dx / length)
        dev = dx - dx.mean()
        var += (dev * dev).sum(); nv += len(dev)
        x = xa % length
        order = np.argsort(x)
        xs, ys, ds = x[order], ya[order], dev[order]
        n = len(xs)
        for i in range(n):
            # partners ahead along x up to half the tray (periodic), each pair once
            ddx = (xs - xs[i]) % length
            sel = (ddx > 0) & (ddx < 0.5 * length)
            ax = ddx[sel]; ay = np.abs(ys[sel] - ys[i]); prod = ds[i] * ds[sel]
            near_x = ax <= reach
            k = np.minimum((ay[near_x] / d).astype(int), len(bins_y) - 1)
            np.add.at(sy, k, prod[near_x]); np.add.at(ny, k, 1)
            near_y = ay <= reach
            k = np.minimum((ax[near_y] / d).astype(int), len(bins_x) - 1)
            np.add.at(sx, k, prod[near_y]); np.add.at(nx, k, 1)
    var /= max(nv, 1)
    print(f"{run}: {halves} half periods from {start} s to {end} s; sd of a grain's move about the mean move {math.sqrt(var)*1e3:.2f} mm; mean diameter {d*1e3:.3f} mm")
    print("across the tray (|dx| <= 2.5 d): |dy| in d, correlation")
    print("  " + "  ".join(f"{k}:{sy[k]/ny[k]/var:+.2f}" for k in range(len(bins_y)) if ny[k] > 0))
    print("along the tray (|dy| <= 2.5 d): |dx| in d, correlation")
    print("  " + "  ".join(f"{k}:{sx[k]/nx[k]/var:+.2f}" for k in range(0, len(bins_x), 2) if nx[k] > 0))


main()
