#!/bin/bash
# The three-way check of the vibrated box (issue 27 section 4): the DEM on
# scenes/vibrated-box-dem.toml, the event-driven model with the DEM's restitution table, and
# with the constant Walton rule fitted to it. Each block writes one comparison directory here.
# Usage: bash scripts/vibrated-box-dem/run.sh [path/to/stripes] (from the repository root).
set -euo pipefail
B=${1:-target/release/stripes}
D=docs/results/vibrated-box-dem
S=scenes/vibrated-box-dem.toml
T="--force --quiet"
# A block whose summary is already here is skipped, so an interrupted script resumes.
have() { [ -s "$D/$1/summary.json" ]; }
# The DEM's restitution tables with plots (the same tables `compare` measures and writes).
have table || $B collide --table --scene $S --g-n 0.01,0.02,0.05,0.1,0.2,0.5,1,2 --out $D/table --force > /dev/null
# The scene as shipped: 100 Hz, V = 0.4 m/s; 5 seeds of 11 s, the first second discarded.
have v0.4 || $B compare $S $T --out $D/v0.4 --seeds 5 --transient 1 --set run.duration=11 > /dev/null
# Twice the peak speed (A0 = 1.273 mm): a more dilute gas.
have v0.8 || $B compare $S $T --out $D/v0.8 --seeds 5 --transient 1 --set run.duration=11 \
  --set drive.amplitude=1.2732e-3 > /dev/null
# Half the peak speed (A0 = 0.318 mm): denser layers near the floor.
have v0.2 || $B compare $S $T --out $D/v0.2 --seeds 5 --transient 1 --set run.duration=11 \
  --set drive.amplitude=3.183e-4 > /dev/null
# Four times stiffer springs at V = 0.4 m/s (k_n = 4e4 N/m; gamma_n and k_t scaled to keep
# eps_n and beta; contacts half as long, so half the step): harder spheres, a slower DEM.
have stiff || $B compare $S $T --out $D/stiff --seeds 3 --transient 1 --set run.duration=6 \
  --set contact.kn=4e4 --set contact.gamma_n=1.08476e-2 --set contact.tangential_stiffness=5080 \
  --set run.dt=5e-7 > /dev/null
# Diagnostics of the difference in H at V = 0.4 m/s.
# One size (every radius 0.5 mm, the table's): is it the table measured at the mean radius?
have mono || $B compare $S $T --out $D/mono --seeds 5 --transient 1 --set run.duration=11 \
  --set particles.radius_min=0.5e-3 --set particles.radius_max=0.5e-3 > /dev/null
# One size in a gap barely wider than it (y walls 1.005 mm apart for spheres of 1 mm): the
# spheres nearly in the plane; is it the motion across the plane?
have planar || $B compare $S $T --out $D/planar --seeds 5 --transient 1 --set run.duration=11 \
  --set particles.radius_min=0.5e-3 --set particles.radius_max=0.5e-3 --set box.width=1.005e-3 > /dev/null
# The event-driven model's collapse guard: t_c of the TC model, 1e-5 s against 1e-6 s.
[ -s $D/tc.json ] || $B events-sweep $D/v0.4/events-table.toml --force --quiet --threads 1 --out $D/tc --seeds 5 \
  --vary guard.tc=1e-5,1e-6 > $D/tc.json
# Section 3's other axes at V = 0.4 m/s, 3 seeds of 11 s each: mu, beta0 through the
# Cundall-Strack spring (-cos(pi sqrt(7 k_t / 2 k_n)) = -0.5, 0, +0.9 without damping), and
# N and L at N/L = 5 grains per mm.
A="--seeds 3 --transient 1 --set run.duration=11"
have axes/mu0 || $B compare $S $T --out $D/axes/mu0 $A --set contact.friction=0 > /dev/null
have axes/mu2 || $B compare $S $T --out $D/axes/mu2 $A --set contact.friction=2 > /dev/null
have axes/mu20 || $B compare $S $T --out $D/axes/mu20 $A --set contact.friction=20 > /dev/null
have axes/kt317 || $B compare $S $T --out $D/axes/kt317 $A --set contact.tangential_stiffness=317.5 > /dev/null
have axes/kt714 || $B compare $S $T --out $D/axes/kt714 $A --set contact.tangential_stiffness=714.3 > /dev/null
have axes/kt2095 || $B compare $S $T --out $D/axes/kt2095 $A --set contact.tangential_stiffness=2095 > /dev/null
have axes/n25 || $B compare $S $T --out $D/axes/n25 $A --set particles.count=25 --set box.length=5e-3 > /dev/null
have axes/n100 || $B compare $S $T --out $D/axes/n100 $A --set particles.count=100 --set box.length=20e-3 > /dev/null
# mu = 0 held in the plane: one size in a gap of 1.005 mm.
have axes/mu0-planar || $B compare $S $T --out $D/axes/mu0-planar $A --set contact.friction=0 \
  --set particles.radius_min=0.5e-3 --set particles.radius_max=0.5e-3 --set box.width=1.005e-3 > /dev/null
