#!/usr/bin/env python3
"""The root crate's module tree at a revision, with line counts by role (issue 42's closing
note): `python3 scripts/house/rooms.py REV [REV ...]` prints, per revision, every file of src/
with its lines and role, then the total per role. Roles, by path (the same rules for the flat
layout before issue 42 and the rooms after it):

  adapters  the command line: main.rs, cli/, and the old commands/ (which held their own run
            directories, claims and summaries beside the argument handling)
  scene     scene text and its checks: scene/, scene_*, events_scene*, bounds
  formats   files written or read back: checkpoints, samples, byte codec, run directories,
            locks, resume rules, VTK, thermo tables, analysis files
  pipeline  a model on a scene: dem/, automaton/, events/ (run, measure, records), analyze/,
            the old pipeline/, host/
  studies   what runs many scenes or models: studies/, the old sweep/, tradeoff/, vibrated_box
"""
import subprocess
import sys

FORMATS = ("checkpoint", "samples", "bytes", "output", "run_lock", "resume", "vtk", "thermo",
           "analysis_files", "analyze/files", "analysis_dir", "analyze/read", "rundir/")
STUDIES = ("studies/", "sweep/", "tradeoff/", "vibrated_box", "calibrate", "coarse")


def role(path):
    p = path[len("src/"):]
    if p == "main.rs" or p.startswith(("cli/", "commands/", "cli_")):
        return "adapters"
    if p.startswith(("scene", "events_scene")) or p == "bounds.rs":
        return "scene"
    if any(k in p for k in FORMATS):
        return "formats"
    if p.startswith(STUDIES) or any(k in p for k in STUDIES):
        return "studies"
    return "pipeline"


def tree(rev):
    names = subprocess.run(["git", "ls-tree", "-r", "--name-only", rev, "src"],
                           capture_output=True, text=True, check=True).stdout.split()
    rows = []
    for n in names:
        if n.endswith(".rs"):
            text = subprocess.run(["git", "show", f"{rev}:{n}"], capture_output=True,
                                  text=True, check=True).stdout
            rows.append((n, text.count("\n"), role(n)))
    return rows


for rev in sys.argv[1:]:
    rows = tree(rev)
    print(f"## {rev}: {len(rows)} files, {sum(r[1] for r in rows)} lines")
    for n, lines, r in rows:
        print(f"{lines:6d}  {r:9s} {n}")
    totals = {}
    for _, lines, r in rows:
        totals[r] = totals.get(r, 0) + lines
    print("by role: " + ", ".join(f"{r} {totals[r]}" for r in sorted(totals)))
    big = [(n, lines) for n, lines, r in rows if r == "adapters" and lines > 150]
    print("adapters over 150 lines: " + (", ".join(f"{n} ({lines})" for n, lines in big) or "none"))
    print()
