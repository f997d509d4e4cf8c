#!/usr/bin/env bash
# Issue 30's goal 3 in on-CPU time: Cundall-Strack (k_t = 50 N/m) and the uncapped floor
# (`wall_friction = inf`) against Haff-Werner on the thesis tray (N = 4000, from the lattice),
# one thread, all three at Haff-Werner's `dt = "auto"`, STEPS steps each. Each round runs the
# three laws back to back with one binary; prints per round the user CPU seconds and each
# law's speed relative to Haff-Werner (Haff-Werner's time / the law's time, so 0.87 means
# 1.15x slower), then the medians. The goal: at least 1 / 1.15 = 0.87.
#
#   bench/laws-cpu.sh BIN
#   STEPS=40000 ROUNDS=7 bench/laws-cpu.sh BIN
set -euo pipefail
cd "$(dirname "$0")/.."
source bench/lib.sh
BIN=$1
STEPS=${STEPS:-20000}
ROUNDS=${ROUNDS:-5}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
scene=scenes/thesis-reference.toml
# Haff-Werner's dt = "auto", read from a one-step run.
dt=$(auto_dt "$BIN" "$scene" "$work/dt" --set run.dt=auto)
user() { # extra --set arguments -> user seconds
  rm -rf "$work/run"
  /usr/bin/time -f "%U" -o "$work/time" "$BIN" run "$scene" --quiet --out "$work/run" \
    --set prepare.duration=0 --set run.dt="$dt" --set run.duration="$(python3 -c "print($STEPS * $dt)")" \
    --set run.threads=1 --set run.checkpoint_interval=0 "$@" > /dev/null 2>&1
  tail -1 "$work/time"
}
printf 'thesis tray, N = 4000, dt = %s s, %s steps, load before: %s\n' "$dt" "$STEPS" "$(uptime | sed 's/.*load/load/')"
cs="" floor=""
for R in $(seq 1 "$ROUNDS"); do
  hw=$(user)
  c=$(user --set contact.tangential=cundall-strack --set contact.tangential_stiffness=50)
  u=$(user --set contact.wall_friction=inf)
  rc=$(python3 -c "print($hw / $c)")
  ru=$(python3 -c "print($hw / $u)")
  printf '  round %d: Haff-Werner %s s, Cundall-Strack %s s (%.3f), uncapped floor %s s (%.3f)\n' "$R" "$hw" "$c" "$rc" "$u" "$ru"
  cs="$cs $rc" floor="$floor $ru"
done
python3 -c "
import statistics, sys
cs, fl = map(float, sys.argv[1].split()), map(float, sys.argv[2].split())
print('  median: Cundall-Strack %.3f, uncapped floor %.3f of Haff-Werner' % (statistics.median(cs), statistics.median(fl)))
" "$cs" "$floor"
printf 'load after: %s\n' "$(uptime | sed 's/.*load/load/')"
