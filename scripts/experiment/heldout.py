"""The held-out numbers of an experiment long run (issue 39): the camera's stripe count at
t3 + T and the stripes in the end-wall zones, read once, from the frames near that time only.

    python3 scripts/experiment/heldout.py RUN_DIR T [OUT_DIR]

t3 is the start of the run's last drive stage (RUN_DIR/scene.toml: 3 Hz / 10 mm after the
fluidising stage). The frames of RUN_DIR/snapshots.bin whose time lies within 1 s of t3 + T
are copied, with the run's header, scene.toml and config.json, into OUT_DIR (default
RUN_DIR-heldout-T), and `stripes analyze` (STRIPES, default target/release/stripes) measures
them as the camera did (one frame per period at +A, in the tray's frame; the analyzer's own
stripe rule, stated in its summary). Printed as one JSON line:
- `count`: the camera count at the strobe frame nearest t3 + T, and `counts_window`: the
  counts at every strobe frame within 1 s of it (their spread is the frame-to-frame noise);
- `end_zones`: the stripes (camera_stripes.csv) at that frame whose centre lies within 0.1 m
  of an end wall (the experiment: grains there try to form stripes and fail, thesis 2.2.6),
  and the empty length at each end (profile.py's measure) at that frame;
- `top_view`: the top view at that frame (OUT_DIR/top_view.png).

A run continued from a committed checkpoint holds zeros for the frames before it
(continue-long-runs.sh): a frame of zeros inside the window is refused, as is a window
without frames.
"""
import csv
import json
import os
import subprocess
import sys
import tomllib

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from window import copy_window  # noqa: E402
HALF_WINDOW_S = 1.0
END_ZONE_M = 0.1


def t3_and_length(run):
    with open(f"{run}/scene.toml", "rb") as fh:
        scene = tomllib.load(fh)
    stages = scene["drive"].get("stages") or []
    return sum(s["duration"] for s in stages[:-1]), scene["box"]["length"]


def main():
    run, after = sys.argv[1], float(sys.argv[2])
    out = sys.argv[3] if len(sys.argv) > 3 else f"{run.rstrip('/')}-heldout-{after:g}"
    t3, length = t3_and_length(run)
    target = t3 + after
    copy_window(run, target - HALF_WINDOW_S, target + HALF_WINDOW_S, out)
    stripes = os.environ.get("STRIPES", "target/release/stripes")
    subprocess.run([stripes, "analyze", out, "--out", f"{out}/analysis", "--force", "--quiet",
                    "--top-view", f"{target}"], check=True, stdout=subprocess.DEVNULL)
    rows = list(csv.DictReader(open(f"{out}/analysis/camera_count.csv")))
    best = min(rows, key=lambda r: abs(float(r["t"]) - target))
    t_best = float(best["t"])
    bands = [r for r in csv.DictReader(open(f"{out}/analysis/camera_stripes.csv"))
             if abs(float(r["t"]) - t_best) < 1e-9]
    centres = sorted(float(r["center"]) for r in bands)
    prof = subprocess.run([sys.executable, f"{HERE}/profile.py", out], capture_output=True,
                          text=True, check=True).stdout
    # profile.py prints times to 0.1 ms: its row nearest the camera's frame.
    rows_p = [l.split() for l in prof.splitlines() if not l.startswith("#")]
    near = min(rows_p, key=lambda f: abs(float(f[0]) - t_best)) if rows_p else None
    empty = [int(near[3]), int(near[4])] if near and abs(float(near[0]) - t_best) < 1e-3 else None
    summary = json.load(open(f"{out}/analysis/summary.json"))
    print(json.dumps({
        "run": run,
        "t3_s": t3,
        "after_t3_s": after,
        "frame_t_s": round(t_best, 4),
        "count": int(best["count"]),
        "contrast": round(float(best["contrast"]), 3),
        "counts_window": [int(r["count"]) for r in rows],
        "frames_window": len(rows),
        "stripe_centres_m": [round(c, 4) for c in centres],
        "end_zones": {
            "stripes_within_0.1m_of_x0": sum(1 for c in centres if c < END_ZONE_M),
            "stripes_within_0.1m_of_xL": sum(1 for c in centres if c > length - END_ZONE_M),
            "empty_mm_x0_xL": empty,
        },
        "rule": summary.get("camera", {}).get("rule"),
        "top_view": f"{out}/analysis/top_view.png",
    }))


if __name__ == "__main__":
    main()
