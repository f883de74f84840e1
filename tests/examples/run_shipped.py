#!/usr/bin/env python3
"""Every example file shipped in scenes/, run through the bristle executable
with the command a user types for it, so that none can break unseen.

The files are found, not listed. Each manifest of scenes/batch/ is a case,
`bristle batch FILE --out DIR --jobs 2`. A painting of scenes/paintings/
(`bristle render FILE -o OUT.png`) or a sheet of scenes/sheets/ (`bristle sheet
FILE -o OUT.png`) is a case of its own unless a shipped manifest already has a
job that renders it: that job runs the same command (`bristle render FILE` in a
child process), so rendering it twice would test nothing more. Cases are named
KIND/STEM (batch/demo, sheet/small); CMake globs the same folders and registers
one ctest test per case, so a new example file is tested without editing a list.

A case fails on a non-zero exit, a missing or unreadable output, or an output
that is not what the file asks for:
  - batch: every job of the manifest rendered (none failed or skipped, the
    output folder starts empty), each job's PNG exists, each stroke and
    painting left visible paint, and each painting's PNG is its canvas's size;
  - painting: the PNG is the canvas's size (size_mm x px_per_mm), and paint
    reached it (the run's --stats count painted pixels);
  - sheet: a PNG, and no cell warned of leaving no paint.
A sheet, and every job of a manifest but a scene's, is rendered at
REDUCED_PX_PER_MM at most (a manifest through a copy whose jobs ask for it,
with its paths made absolute): a render's cost grows with its pixels, and the
strokes, cells, labels and layout are the same at any resolution. A scene
sets its own resolution, and its jobs run as shipped.

  run_shipped.py --list                   the cases, ';'-separated (for CMake)
  run_shipped.py --covered                each file and the case that runs it
  run_shipped.py --bristle BIN CASE...    runs them (exit 1 if any fails)
  run_shipped.py --bristle BIN --keep DIR batch/STEM
                                          a batch writes to DIR (emptied first) and
                                          leaves its PNGs there: the golden test
                                          compares the paintings' as they are
                                          (scripts/golden.py --rendered)
"""

import argparse
import json
import os
import shutil
import struct
import subprocess
import sys
import tempfile
from pathlib import Path

SRC = Path(__file__).resolve().parents[2]
KINDS = {"batch": "scenes/batch", "painting": "scenes/paintings", "sheet": "scenes/sheets"}
# 3 px/mm keeps a hair's footprint (0.1-0.3 mm wide) within a pixel or two,
# as the sheets' own resolutions (4-6 px/mm) and a stroke's default (8) do, at
# a quarter of the pixels or less.
REDUCED_PX_PER_MM = 3
# A job's keys that name a file, relative to its manifest.
PATH_KEYS = ("brush", "trajectory", "sheet", "preview", "scene")


def manifest_renders():
    """{file a shipped manifest's job renders (resolved): the manifest's case}."""
    covered = {}
    for m in sorted((SRC / KINDS["batch"]).glob("*.json")):
        for job in json.loads(m.read_text()).get("jobs", []):
            for key in ("scene", "sheet"):
                if key in job:
                    covered.setdefault((m.parent / job[key]).resolve(), f"batch/{m.stem}")
    return covered


def coverage():
    """[(file, the case that runs it)] for every shipped example file."""
    covered = manifest_renders()
    out = []
    for kind, folder in KINDS.items():
        for f in sorted((SRC / folder).glob("*.json")):
            out.append((f, covered.get(f.resolve(), f"{kind}/{f.stem}")))
    return out


def cases():
    seen = []
    for _, case in coverage():
        if case not in seen:
            seen.append(case)
    return seen


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


def reduced_manifest(src, tmp):
    """A copy of the manifest src in tmp whose jobs, a scene's excepted, render
    at REDUCED_PX_PER_MM at most, its file paths made absolute."""
    manifest = json.loads(src.read_text())
    for job in manifest["jobs"]:
        for key in PATH_KEYS:
            if isinstance(job.get(key), str) and (src.parent / job[key]).exists():
                job[key] = str((src.parent / job[key]).resolve())
        if "scene" not in job:
            options = job.setdefault("options", {})
            options["px-per-mm"] = min(options.get("px-per-mm", REDUCED_PX_PER_MM),
                                       REDUCED_PX_PER_MM)
    copy = tmp / src.name
    copy.write_text(json.dumps(manifest, indent=2))
    return copy


def check_batch(bristle, src, tmp, keep=None):
    out = tmp / "out"
    if keep is not None:
        shutil.rmtree(keep, ignore_errors=True)
        out = keep
    code, stdout, err = run(bristle, ["batch", str(reduced_manifest(src, tmp)), "--out", str(out),
                                      "--jobs", "2", "--json"], tmp)
    records = [json.loads(line) for line in stdout.splitlines() if line.strip()]
    if code != 0:
        # With --json a failed job's error is in its record, not on stderr.
        failed = [f"job '{r['job']}': {r.get('error', '')}" for r in records
                  if r.get("status") == "failed"]
        return [f"exit {code}: {err.strip()[-400:]}", *failed[:3]]
    problems = []
    manifest = json.loads(src.read_text())
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
            size = png_size(png)
        except (OSError, ValueError) as e:
            problems.append(f"job '{job['id']}': {e}")
            continue
        # A stroke's or a painting's figures: paint reached the canvas.
        if "figures" in r and r["figures"].get("painted_pixels", 0) <= 0:
            problems.append(f"job '{job['id']}': no visible paint: {r['figures']}")
        if "scene" in job:
            want = canvas_px(src.parent / job["scene"])
            if size != want:
                problems.append(f"job '{job['id']}': the PNG is {size} px, the canvas {want}")
    return problems


def canvas_px(scene_path):
    canvas = json.loads(Path(scene_path).read_text())["canvas"]
    return tuple(round(s * canvas["px_per_mm"]) for s in canvas["size_mm"])


def painted_pixels(stats_path):
    stats = json.loads(Path(stats_path).read_text())
    return stats.get("painted_pixels", stats.get("figures", {}).get("painted_pixels", 0))


def check_painting(bristle, src, tmp):
    png, stats = tmp / "painting.png", tmp / "stats.json"
    code, _, err = run(bristle, ["render", "-q", str(src), "-o", str(png), "--stats", str(stats)],
                       tmp)
    if code != 0:
        return [f"exit {code}: {err.strip()[-400:]}"]
    want = canvas_px(src)
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
    if sheet.get("px_per_mm", 0) > REDUCED_PX_PER_MM:
        args += ["--px-per-mm", str(REDUCED_PX_PER_MM)]
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
    ap.add_argument("--covered", action="store_true")
    ap.add_argument("--bristle")
    ap.add_argument("--keep", type=Path, help="a batch's output folder, kept")
    ap.add_argument("cases", nargs="*")
    a = ap.parse_args()
    if a.list:
        print(";".join(cases()))
        return 0
    if a.covered:
        for f, case in coverage():
            print(f"{f.relative_to(SRC)}: {case}")
        return 0
    bristle = str(Path(a.bristle).resolve())
    checks = {"batch": check_batch, "painting": check_painting, "sheet": check_sheet}
    failed = 0
    for case in a.cases:
        kind, stem = case.split("/", 1)
        src = SRC / KINDS[kind] / f"{stem}.json"
        with tempfile.TemporaryDirectory(prefix="bristle-shipped-") as tmp:
            try:
                if a.keep is not None and kind != "batch":
                    raise ValueError("--keep is for a batch case")
                extra = {"keep": a.keep.resolve()} if a.keep is not None else {}
                problems = checks[kind](bristle, src, Path(tmp), **extra)
            except (OSError, ValueError, KeyError) as e:
                problems = [f"{type(e).__name__}: {e}"]
        for p in problems:
            print(f"{case}: {p}")
        print(f"{case}: {'FAIL' if problems else 'ok'}")
        failed += bool(problems)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
