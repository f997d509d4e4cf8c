#!/usr/bin/env bash
# bench: scripts/rolling-sds/sds-cost.sh target/release/stripes
# User CPU seconds of one-thread stripe-scene runs, Brilliantov-Poschel (as shipped) against
# sds (mu_r 0.1, default stiffness), same step 6e-6 s, 20000 steps from the lattice.
W=$(mktemp -d)
for r in 1 2 3; do
  for law in bp sds; do
    if [ $law = sds ]; then extra="--set contact.rolling=sds --set contact.rolling_resistance=0.1"; else extra=""; fi
    /usr/bin/time -f "%U" -o $W/t nice -n 10 "$1" run scenes/stripes.toml --quiet --out $W/run --force \
      --set prepare.duration=0 --set run.dt=6e-6 --set run.duration=0.12 --set run.threads=1 \
      --set run.checkpoint_interval=0 $extra > $W/log 2>&1
    echo "round $r $law user $(tail -1 $W/t)"
  done
done
rm -rf $W
