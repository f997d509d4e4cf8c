"""Density profiles of an experiment run in the tray's frame (x - u(t)), from snapshots.bin.

    python3 scripts/experiment/profile.py RUN_DIR [BIN_MM]

The tray moves: with end walls a grain's lab x is its place in the tray plus the tray's
displacement u(t), so a profile along the tray subtracts u(t) of the run's own drive schedule
(read from RUN_DIR/scene.toml: its [[drive.stages]], each from a zero crossing, or its one
drive.frequency / drive.amplitude). Prints, per frame: time, stage, the empty length at each end (the distance from the
end wall to the first bin holding at least a tenth of the mean count), the coefficient of
variation of the counts in bins of BIN_MM (default 20 mm) over the tray, and the count profile.
"""
import math
import struct
import sys
import tomllib

run = sys.argv[1]
bin_mm = float(sys.argv[2]) if len(sys.argv) > 2 else 20.0


def stages_of(run_dir):
    """(start s, Hz, m) of each stage of the run's drive (scene.toml)."""
    with open(f"{run_dir}/scene.toml", "rb") as fh:
        drive = tomllib.load(fh)["drive"]
    if not drive.get("stages"):
        return [(0.0, drive["frequency"], drive["amplitude"])]
    out, start = [], 0.0
    for st in drive["stages"]:
        out.append((start, st["frequency"], st["amplitude"]))
        start += st["duration"]
    return out


STAGES = stages_of(run)


def u(t):
    start, f, a = [s for s in STAGES if s[0] <= t][-1]
    return a * math.sin(2 * math.pi * f * (t - start))


with open(f"{run}/snapshots.bin", "rb") as fh:
    data = fh.read()
assert data[:8] == b"STRPSNP1"
n, = struct.unpack_from("<Q", data, 8)
length, width = struct.unpack_from("<dd", data, 16)
off = 32 + 8 * n
size = 8 + 24 * n
nbins = int(round(length * 1000 / bin_mm))
print(f"# {n} grains, tray {length} x {width} m, bins of {bin_mm} mm")
print("# t_s stage u_mm empty_x0_mm empty_xL_mm cv counts")
while off + size <= len(data):
    t, = struct.unpack_from("<d", data, off)
    rec = struct.unpack_from(f"<{6 * n}f", data, off + 8)
    off += size
    shift = u(t)
    counts = [0] * nbins
    for i in range(n):
        x = rec[6 * i] - shift
        k = min(max(int(x / length * nbins), 0), nbins - 1)
        counts[k] += 1
    mean = n / nbins
    cv = math.sqrt(sum((c - mean) ** 2 for c in counts) / nbins) / mean
    # Empty ends at 1 mm resolution: first mm-bin from each wall with any grain centre.
    fine = [0] * int(length * 1000)
    for i in range(n):
        x = rec[6 * i] - shift
        fine[min(max(int(x * 1000), 0), len(fine) - 1)] += 1
    # an end is "empty" up to the first 10 mm window holding a tenth of the mean count
    per10 = n / (length * 100) * 0.1
    def empty(seq):
        for j in range(len(seq)):
            if sum(seq[j:j + 10]) >= per10:
                return j
        return len(seq)
    stage = len([s for s in STAGES if s[0] <= t])
    print(f"{t:.4f} {stage} {1000 * shift:+.2f} {empty(fine)} {empty(fine[::-1])} {cv:.3f} " + " ".join(map(str, counts)))
