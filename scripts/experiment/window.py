"""Copy the frames of a run's snapshots.bin whose time lies in [FROM, TO] into a run folder of
their own (header, scene.toml, config.json), so that `stripes analyze` measures only them.

    python3 scripts/experiment/window.py RUN_DIR FROM TO OUT_DIR

A run continued from a committed checkpoint on another machine holds zeros for the frames
before it (continue-long-runs.sh): a frame of zeros inside the window is refused, and so is a
window without frames. Frames are streamed, one at a time.
"""
import os
import shutil
import struct
import sys


def copy_window(run, lo, hi, out):
    """Copies the frames with lo <= t <= hi; returns their times."""
    snap = f"{run}/snapshots.bin"
    with open(snap, "rb") as fh:
        head = fh.read(16)
        if head[:8] != b"STRPSNP1":
            sys.exit(f"{snap}: not a stripes snapshot file")
        n = struct.unpack("<Q", head[8:16])[0]
        header_bytes = 32 + 8 * n
        frame_bytes = 8 + 24 * n
        frames = (os.path.getsize(snap) - header_bytes) // frame_bytes
        fh.seek(0)
        header = fh.read(header_bytes)

        def time_of(k):
            fh.seek(header_bytes + k * frame_bytes)
            return struct.unpack("<d", fh.read(8))[0]

        # Frames are in time order (zeros before a committed checkpoint read as t = 0):
        # the window's first frame by bisection.
        first, last = 0, frames
        while first < last:
            mid = (first + last) // 2
            if time_of(mid) < lo:
                first = mid + 1
            else:
                last = mid
        if os.path.exists(out):
            shutil.rmtree(out)
        os.makedirs(out)
        times = []
        with open(f"{out}/snapshots.bin", "wb") as dst:
            dst.write(header)
            for k in range(first, frames):
                fh.seek(header_bytes + k * frame_bytes)
                body = fh.read(frame_bytes)
                t = struct.unpack("<d", body[:8])[0]
                if t > hi:
                    break
                if t == 0.0 or not any(body[8:]):
                    sys.exit(f"{snap}: frame {k} in the window is zeros (before the checkpoint the run continued from)")
                dst.write(body)
                times.append(t)
    if not times:
        sys.exit(f"{snap}: no frame in [{lo}, {hi}] s ({frames} frames on disk)")
    for name in ("scene.toml", "config.json"):
        shutil.copy(f"{run}/{name}", f"{out}/{name}")
    return times


if __name__ == "__main__":
    t = copy_window(sys.argv[1], float(sys.argv[2]), float(sys.argv[3]), sys.argv[4])
    print(f"{len(t)} frames, {t[0]} to {t[-1]} s")
