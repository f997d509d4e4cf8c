"""The long runs' window table (docs/results/experiment/study.md): the camera's count and
contrast over time spans, from a window's analysis (`stripes analyze OUT`, then this on
OUT/analysis/camera_count.csv).

    python3 scripts/experiment/window-table.py CAMERA_COUNT_CSV EDGE0 EDGE1 ... EDGEn

prints a Markdown table with one column per span [EDGE_k, EDGE_k+1) s: the mean and the largest
count, and the mean contrast, over the frames in that span.
"""
import csv
import sys

rows = list(csv.DictReader(open(sys.argv[1])))
edges = [float(e) for e in sys.argv[2:]]
spans = list(zip(edges, edges[1:]))
cells = {"camera count, mean": [], "largest count": [], "contrast, mean": [], "frames": []}
for lo, hi in spans:
    inside = [r for r in rows if lo <= float(r["t"]) < hi]
    counts = [int(float(r["count"])) for r in inside]
    contrast = [float(r["contrast"]) for r in inside]
    cells["camera count, mean"].append(f"{sum(counts) / len(counts):.2f}" if counts else "-")
    cells["largest count"].append(str(max(counts)) if counts else "-")
    cells["contrast, mean"].append(f"{sum(contrast) / len(contrast):.2f}" if contrast else "-")
    cells["frames"].append(str(len(inside)))
print("| t (s) | " + " | ".join(f"{lo:g}-{hi:g}" for lo, hi in spans) + " |")
print("|---|" + "---|" * len(spans))
for name, values in cells.items():
    print(f"| {name} | " + " | ".join(values) + " |")
