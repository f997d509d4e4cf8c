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
import shutil
import struct
import subprocess
import sys
import tomllib

HERE = os.path.dirname(os.path.abspath(__file__))
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
    snap = f"{run}/snapshots.bin"
    with open(snap, "rb") as fh:
        head = fh.read(16)
        if head[:8] != b"STRPSNP1":
            sys.exit(f"{snap}: not a stripes snapshot file")
        n = struct.unpack("<Q", head[8:16])[0]
        header_bytes = 32 + 8 * n
        frame_bytes = 8 + 24 * n
        size = os.path.getsize(snap)
        frames = (size - header_bytes) // frame_bytes
        fh.seek(0)
        header = fh.read(header_bytes)
        # Frames are one per period in time order: find the window by bisection on the
        # written frames' times (zeros before a committed checkpoint read as t = 0).
        def time_of(k):
            fh.seek(header_bytes + k * frame_bytes)
            return struct.unpack("<d", fh.read(8))[0]

        lo, hi = 0, frames
        while lo < hi:
            mid = (lo + hi) // 2
            if time_of(mid) < target - HALF_WINDOW_S:
                lo = mid + 1
            else:
                hi = mid
        picked = []
        k = lo
        while k < frames:
            t = time_of(k)
            if t > target + HALF_WINDOW_S:
                break
            fh.seek(header_bytes + k * frame_bytes)
            body = fh.read(frame_bytes)
            if t == 0.0 or not any(body[8:]):
                sys.exit(f"{snap}: frame {k} in the window is zeros (before the checkpoint the run continued from)")
            picked.append((t, body))
            k += 1
    if not picked:
        sys.exit(f"{snap}: no frame within {HALF_WINDOW_S} s of t = {target} s ({frames} frames on disk)")
    if os.path.exists(out):
        shutil.rmtree(out)
    os.makedirs(out)
    with open(f"{out}/snapshots.bin", "wb") as fh:
        fh.write(header)
        for _, body in picked:
            fh.write(body)
    for name in ("scene.toml", "config.json"):
        shutil.copy(f"{run}/{name}", f"{out}/{name}")
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
