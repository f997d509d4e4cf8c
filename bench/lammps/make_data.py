#!/usr/bin/env python3
"""LAMMPS data file of the thesis tray: N grains with radii uniform in [0.25, 0.5] mm on a
one-layer lattice resting on the floor (z = R), random vx, vy in [-5, 5] mm/s, as the
stripes sample before relaxation (particles::prepare::initial_state). Usage:
make_data.py N LENGTH WIDTH SEED OUT"""
import math, random, sys

n, length, width, seed, out = int(sys.argv[1]), float(sys.argv[2]), float(sys.argv[3]), int(sys.argv[4]), sys.argv[5]
rmin, rmax, rho, speed = 0.25e-3, 0.5e-3, 2500.0, 0.005
rng = random.Random(seed)
spacing = 2.1 * rmax
nx = max(1, int(length // spacing))
ny = max(1, int((width - 2 * rmax) // spacing) + 1)
if n > nx * ny:
    sys.exit(f"{n} grains do not fit in one layer of {nx * ny} sites")
sites = sorted(rng.sample(range(nx * ny), n))
dy = (width - 2 * rmax * 1.05) / (ny - 1) if ny > 1 else 0.0
with open(out, "w") as f:
    f.write(f"stripes thesis tray, {n} grains\n\n{n} atoms\n1 atom types\n\n")
    f.write(f"0 {length} xlo xhi\n0 {width} ylo yhi\n-0.001 0.1 zlo zhi\n\nAtoms # sphere\n\n")
    vel = []
    for k, s in enumerate(sites):
        ix, iy = s % nx, s // nx
        r = rng.uniform(rmin, rmax)
        x = (ix + 0.5) * length / nx
        y = 1.05 * rmax + iy * dy if ny > 1 else 0.5 * width
        f.write(f"{k + 1} 1 {2 * r!r} {rho} {x!r} {y!r} {r!r}\n")
        vel.append((rng.uniform(-speed, speed), rng.uniform(-speed, speed)))
    f.write("\nVelocities\n\n")
    for k, (vx, vy) in enumerate(vel):
        f.write(f"{k + 1} {vx!r} {vy!r} 0 0 0 0\n")
