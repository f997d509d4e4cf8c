"""The first seconds of an experiment run at 3 Hz / 10 mm, in the experiment's clock (issue 39's
early targets), from an analysed run (`stripes analyze RUN`) and its snapshots.

    python3 scripts/experiment/early.py RUN_DIR [RUN_DIR ...]

The experiment's camera starts when the drive is lowered to 3 Hz / 10 mm; here that is the start
`t3` of the run's last stage (RUN_DIR/scene.toml), whatever fluidising stages came before. For
each run it prints, with times counted from t3:
- the camera's count (analysis/camera_count.csv, one frame per period at +A in the tray frame)
  at the frames nearest t3 + 2, 4, 6, 10 s, and the largest count after t3;
- the cluster and stripe onsets by the analyzer's own rule (the first frame from which every
  later frame has contrast >= 1.5, resp. at least one stripe: analysis::stripes::onset), taken
  over the frames from t3 on only, so a layer that already holds clusters or bands when the
  drive is lowered shows onset 0;
- the phase (summary of the analysis, over the whole run);
- the empty length at each end wall (scripts/experiment/profile.py's measure: distance from the
  wall to the first 10 mm window holding a tenth of the mean count), averaged over the frames of
  the period before t3 and of the last period of the run.
The counts after t3 + 10 s are not printed (the held-out counts are never read here: run it on a
run that stops at t3 + 10 to 12 s).
"""
import csv
import json
import os
import subprocess
import sys
import tomllib

HERE = os.path.dirname(os.path.abspath(__file__))


def t3_of(run):
    with open(f"{run}/scene.toml", "rb") as fh:
        drive = tomllib.load(fh)["drive"]
    st = drive.get("stages") or []
    return sum(s["duration"] for s in st[:-1]), st


def onset(times, flags):
    last_zero = max((k for k, f in enumerate(flags) if not f), default=None)
    if last_zero is None:
        return times[0] if times else None
    return times[last_zero + 1] if last_zero + 1 < len(times) else None


def main():
    for run in sys.argv[1:]:
        t3, stages = t3_of(run)
        rows = list(csv.DictReader(open(f"{run}/analysis/camera_count.csv")))
        t = [float(r["t"]) for r in rows]
        n = [int(r["count"]) for r in rows]
        c = [float(r["contrast"]) for r in rows]
        after = [k for k in range(len(t)) if t[k] >= t3 - 1e-9 and t[k] <= t3 + 12.0]
        ta = [t[k] - t3 for k in after]
        cluster = onset(ta, [c[k] >= 1.5 for k in after])
        stripe = onset(ta, [n[k] >= 1 for k in after])
        at = {}
        for s in (2, 4, 6, 10):
            k = min(after, key=lambda k: abs(t[k] - t3 - s))
            at[s] = (n[k], round(t[k] - t3, 2))
        summ = json.load(open(f"{run}/analysis/summary.json")) if os.path.exists(f"{run}/analysis/summary.json") else {}
        prof = subprocess.run([sys.executable, f"{HERE}/profile.py", run], capture_output=True, text=True, check=True).stdout
        fr = [l.split() for l in prof.splitlines() if not l.startswith("#")]
        fr = [(float(f[0]), int(f[3]), int(f[4])) for f in fr]
        tend = fr[-1][0]
        period3 = 1.0 / stages[-1]["frequency"] if stages else 1.0 / 3.0

        def ends(lo, hi):
            sel = [f for f in fr if lo <= f[0] < hi]
            if not sel:
                return None
            return (round(sum(f[1] for f in sel) / len(sel)), round(sum(f[2] for f in sel) / len(sel)))

        pre_period = 1.0 / stages[-2]["frequency"] if len(stages) > 1 else period3
        out = {
            "run": run,
            "t3_s": t3,
            "phase": summ.get("phase"),
            "contrast": summ.get("contrast"),
            "count_at": {f"+{s}": at[s][0] for s in at},
            "count_max_after_t3": max((n[k] for k in after), default=None),
            "cluster_onset_after_t3_s": cluster,
            "stripe_onset_after_t3_s": stripe,
            "contrast_at_t3": round(c[after[0]], 2) if after else None,
            "empty_ends_mm_before_t3": ends(t3 - pre_period, t3 + 1e-9) if t3 > 0 else ends(0, 1e-9),
            "empty_ends_mm_last_period": ends(tend - period3 + 1e-6, tend + 1),
            "t_end_s": round(tend, 3),
        }
        print(json.dumps(out))


main()
