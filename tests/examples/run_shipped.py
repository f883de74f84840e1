#!/usr/bin/env python3
"""Every example file shipped in scenes/, run through the bristle executable
with the command a user types for it, so that none can break unseen.

The files are found, not listed: each *.json of
  scenes/batch/      `bristle batch FILE --out DIR --jobs 2`
  scenes/paintings/  `bristle render FILE -o OUT.png`
  scenes/sheets/     `bristle sheet FILE -o OUT.png`
is one case, named KIND/STEM (batch/demo, painting/petals, sheet/library), so a
new example file is tested without editing anything (CMake globs the same
folders and registers one ctest test per case).

A case fails on a non-zero exit, a missing or unreadable output, or an output
that is not what the file asks for:
  - batch: every job of the manifest rendered (none failed or skipped, the
    output folder starts empty) and each job's PNG exists and carries its key;
  - painting: the PNG is the canvas's size (size_mm x px_per_mm), and paint
    reached it (the run's --stats count painted pixels);
  - sheet: a PNG, and no cell warned of leaving no paint.
A sheet is rendered at SHEET_PX_PER_MM at most: a sheet's cost grows with its
pixels as well as its strokes, and the cells, labels and layout are the same
at any resolution (the full library sheet is the demo's and has its golden).

  run_shipped.py --list                   the cases, ';'-separated (for CMake)
  run_shipped.py --bristle BIN CASE...    runs them (exit 1 if any fails)
"""

import argparse
import json
import os
import struct
import subprocess
import sys
import tempfile
from pathlib import Path

SRC = Path(__file__).resolve().parents[2]
KINDS = {"batch": "scenes/batch", "painting": "scenes/paintings", "sheet": "scenes/sheets"}
# 3 px/mm keeps a hair's footprint (0.1-0.3 mm wide) within a pixel or two,
# as the sheets' own resolutions (4-6 px/mm) do, at a quarter of the pixels.
SHEET_PX_PER_MM = 3


def cases():
    out = []
    for kind, folder in KINDS.items():
        for f in sorted((SRC / folder).glob("*.json")):
            out.append(f"{kind}/{f.stem}")
    return out


def png_size(path):
    with open(path, "rb") as f:
        head = f.read(24)
    if len(head) < 24 or head[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError(f"{path}: not a PNG")
    return struct.unpack(">II", head[16:24])


def run(bristle, args, cwd):
    env = dict(os.environ)
    env.pop("GALLIUM_DRIVER", None)  # an unknown driver crashes OSMesa
    p = subprocess.run([bristle, *args], cwd=cwd, env=env, stdin=subprocess.DEVNULL,
                       capture_output=True, text=True)
    return p.returncode, p.stdout, p.stderr


def check_batch(bristle, src, tmp):
    out = tmp / "out"
    code, stdout, err = run(bristle, ["batch", str(src), "--out", str(out), "--jobs", "2",
                                      "--json"], tmp)
    if code != 0:
        return [f"exit {code}: {err.strip()[-400:]}"]
    problems = []
    manifest = json.loads(src.read_text())
    records = [json.loads(line) for line in stdout.splitlines() if line.strip()]
    summary = [r for r in records if r.get("summary")]
    jobs = {r["job"]: r for r in records if not r.get("summary")}
    if len(summary) != 1 or summary[0]["rendered"] != len(manifest["jobs"]):
        problems.append(f"not every job rendered: {summary}")
    for job in manifest["jobs"]:
        r = jobs.get(job["id"])
        if r is None or r["status"] != "rendered":
            problems.append(f"job '{job['id']}': {r}")
            continue
        png = Path(r["output"])
        png = png if png.is_absolute() else tmp / png
        try:
            png_size(png)
        except (OSError, ValueError) as e:
            problems.append(f"job '{job['id']}': {e}")
    return problems


def painted_pixels(stats_path):
    stats = json.loads(Path(stats_path).read_text())
    return stats.get("painted_pixels", stats.get("figures", {}).get("painted_pixels", 0))


def check_painting(bristle, src, tmp):
    png, stats = tmp / "painting.png", tmp / "stats.json"
    code, _, err = run(bristle, ["render", "-q", str(src), "-o", str(png), "--stats", str(stats)],
                       tmp)
    if code != 0:
        return [f"exit {code}: {err.strip()[-400:]}"]
    scene = json.loads(src.read_text())
    canvas = scene["canvas"]
    want = tuple(round(s * canvas["px_per_mm"]) for s in canvas["size_mm"])
    problems = []
    if png_size(png) != want:
        problems.append(f"the PNG is {png_size(png)} px, the canvas {want}")
    if painted_pixels(stats) <= 0:
        problems.append(f"no paint reached the canvas: {stats.read_text()[:300]}")
    return problems


def check_sheet(bristle, src, tmp):
    png = tmp / "sheet.png"
    sheet = json.loads(src.read_text())
    args = ["sheet", "-q", str(src), "-o", str(png)]
    if sheet.get("px_per_mm", 0) > SHEET_PX_PER_MM:
        args += ["--px-per-mm", str(SHEET_PX_PER_MM)]
    code, _, err = run(bristle, args, tmp)
    if code != 0:
        return [f"exit {code}: {err.strip()[-400:]}"]
    # Sheets warn about a cell with no visible paint; none of ours may.
    if "no visible paint" in err:
        return [f"a cell left no paint: {err.strip()[-400:]}"]
    png_size(png)
    return []


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--list", action="store_true")
    ap.add_argument("--bristle")
    ap.add_argument("cases", nargs="*")
    a = ap.parse_args()
    if a.list:
        print(";".join(cases()))
        return 0
    bristle = str(Path(a.bristle).resolve())
    checks = {"batch": check_batch, "painting": check_painting, "sheet": check_sheet}
    failed = 0
    for case in a.cases:
        kind, stem = case.split("/", 1)
        src = SRC / KINDS[kind] / f"{stem}.json"
        with tempfile.TemporaryDirectory(prefix="bristle-shipped-") as tmp:
            try:
                problems = checks[kind](bristle, src, Path(tmp))
            except (OSError, ValueError, KeyError) as e:
                problems = [f"{type(e).__name__}: {e}"]
        for p in problems:
            print(f"{case}: {p}")
        print(f"{case}: {'FAIL' if problems else 'ok'}")
        failed += bool(problems)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
