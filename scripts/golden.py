#!/usr/bin/env python3
"""The golden-image suite of bristle (docs/golden-tests.md).

  golden.py run    [NAME...]  render the goldens, compare them with `bristle compare`,
                              write an HTML report; exit 0 all pass, 1 any fails
  golden.py update [NAME...]  re-render and store the goldens that fail or are new
                              (--force: every selected golden)

Each golden of golden/golden.json is a stroke (brush + trajectory + render
options) or a scene, its PNG golden/<name>.png and a tolerance preset of
`bristle compare` (exact, strict, loose). Renders run --jobs at a time.
--rendered-by MANIFEST --rendered DIR: a scene golden that a job of the batch
manifest MANIFEST renders with the same command (its id the golden's name, the
same scene, no options) is compared as that batch wrote it, DIR/<name>.png,
instead of rendered again.
Exit codes: 0 pass, 1 a golden failed, 64 usage, 65 bad manifest, 66 missing input.
"""

import argparse
import concurrent.futures
import html
import json
import os
import re
import shlex
import shutil
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
PRESETS = ("exact", "strict", "loose")
NAME_RE = re.compile(r"^[a-z0-9][a-z0-9-]*$")
# Render errors and compare messages shown in the report: the last lines are
# the ones that say what went wrong.
STDERR_TAIL_LINES = 12


class ManifestError(Exception):
    pass


def die(code, message):
    print(f"golden: {message}", file=sys.stderr)
    sys.exit(code)


def load_manifest(path):
    """The goldens of a bristle-golden/1 file, paths made absolute."""
    try:
        with open(path, encoding="utf-8") as f:
            doc = json.load(f)
    except OSError as e:
        die(66, f"{path}: cannot read: {e.strerror}")
    except json.JSONDecodeError as e:
        die(65, f"{path}: line {e.lineno}: malformed JSON: {e.msg}")
    base = os.path.dirname(os.path.abspath(path))

    def bad(where, rule):
        raise ManifestError(f"{path}: {where}: {rule}")

    if not isinstance(doc, dict) or doc.get("format") != "bristle-golden/1":
        bad("/format", 'must be "bristle-golden/1"')
    unknown = set(doc) - {"format", "description", "goldens"}
    if unknown:
        bad("/" + sorted(unknown)[0], "unknown key")
    goldens = doc.get("goldens")
    if not isinstance(goldens, list) or not goldens:
        bad("/goldens", "must be a non-empty list")
    seen = set()
    out = []
    for i, g in enumerate(goldens):
        at = f"/goldens/{i}"
        if not isinstance(g, dict):
            bad(at, "must be an object")
        unknown = set(g) - {"name", "brush", "trajectory", "scene", "options", "tolerance"}
        if unknown:
            bad(f"{at}/{sorted(unknown)[0]}", "unknown key")
        name = g.get("name")
        if not isinstance(name, str) or not NAME_RE.match(name):
            bad(f"{at}/name", "must be lower-case letters, digits and '-'")
        if name in seen:
            bad(f"{at}/name", f"'{name}' is listed twice")
        seen.add(name)
        is_scene = "scene" in g
        if is_scene == ("brush" in g or "trajectory" in g):
            bad(at, "needs either 'scene' or both 'brush' and 'trajectory'")
        if not is_scene and not ("brush" in g and "trajectory" in g):
            bad(at, "a stroke needs both 'brush' and 'trajectory'")
        for key in ("scene", "brush", "trajectory"):
            if key in g and (not isinstance(g[key], str) or not g[key]):
                bad(f"{at}/{key}", "must be a path")
        options = g.get("options", [])
        if not isinstance(options, list) or not all(isinstance(o, str) for o in options):
            bad(f"{at}/options", "must be a list of strings")
        if is_scene and options:
            bad(f"{at}/options", "a scene carries its own options")
        if g.get("tolerance") not in PRESETS:
            bad(f"{at}/tolerance", "must be exact, strict or loose")
        entry = {"name": name, "tolerance": g["tolerance"], "options": options,
                 "png": os.path.join(base, name + ".png")}
        for key in ("scene", "brush", "trajectory"):
            if key in g:
                entry[key] = os.path.normpath(os.path.join(base, g[key]))
        out.append(entry)
    return out


def bristle_env():
    env = dict(os.environ)
    # An unknown GALLIUM_DRIVER crashes OSMesa; the goldens are llvmpipe's.
    env.pop("GALLIUM_DRIVER", None)
    return env


def render_command(bristle, g, output):
    if "scene" in g:
        return [bristle, "render", g["scene"], "-o", output, "--quiet"]
    return [bristle, "render", "--brush", g["brush"], "--trajectory", g["trajectory"],
            "-o", output, "--quiet"] + g["options"]


def tail(text):
    return "\n".join(text.strip().splitlines()[-STDERR_TAIL_LINES:])


def batch_renders(manifest_path, goldens):
    """{golden name: its PNG relative to the batch's --out} for every scene
    golden that a job of the batch manifest renders with the golden's own
    command: `bristle batch` runs a scene job as `bristle render SCENE -o OUT`
    (docs/batch.md), so a job whose id is the golden's name, whose scene is the
    golden's and which adds no options, neither its own nor the manifest's
    defaults, makes the golden's pixels."""
    try:
        with open(manifest_path, encoding="utf-8") as f:
            doc = json.load(f)
        jobs = doc["jobs"]
        defaults = doc.get("defaults", {}).get("options")
    except (OSError, ValueError, KeyError, TypeError, AttributeError) as e:
        die(66, f"{manifest_path}: cannot read its jobs: {e}")
    if defaults:
        return {}
    base = os.path.dirname(os.path.abspath(manifest_path))
    scenes = {g["name"]: g["scene"] for g in goldens if "scene" in g}
    return {j["id"]: j.get("output", j["id"] + ".png") for j in jobs
            if isinstance(j, dict) and j.get("id") in scenes and not j.get("options")
            and isinstance(j.get("scene"), str)
            and os.path.normpath(os.path.join(base, j["scene"])) == scenes[j["id"]]}


def check_one(bristle, g, work, rendered=None):
    """Renders one golden into work/new (or takes the PNG rendered, as a batch
    rendered it) and compares it with its PNG."""
    new_png = os.path.join(work, "new", g["name"] + ".png")
    diff_png = os.path.join(work, "diff", g["name"] + ".png")
    for stale in (new_png, diff_png):
        if os.path.exists(stale):
            os.remove(stale)
    result = {"name": g["name"], "tolerance": g["tolerance"], "new": new_png,
              "reference": g["png"], "diff": None, "metrics": None}
    cmd = render_command(bristle, g, new_png)
    result["command"] = shlex.join(cmd)
    started = time.monotonic()
    if rendered:
        # The batch's own render of the same command, copied so that the report
        # shows it beside the golden.
        result["command"] += f"  (as the batch rendered it: {rendered})"
        if not os.path.exists(rendered):
            result.update(status="error", render_s=0.0,
                          reason=f"the batch did not render {rendered}")
            return result
        shutil.copyfile(rendered, new_png)
    else:
        r = subprocess.run(cmd, capture_output=True, text=True, env=bristle_env())
        if r.returncode != 0:
            result.update(status="error", render_s=time.monotonic() - started,
                          reason=f"render exit {r.returncode}: {tail(r.stderr)}")
            return result
    result["render_s"] = time.monotonic() - started
    if not os.path.exists(g["png"]):
        result.update(status="missing", reason=f"no golden image {g['png']}")
        return result
    c = subprocess.run([bristle, "compare", g["png"], new_png, "--tolerance", g["tolerance"],
                        "--json", "--diff", diff_png],
                       capture_output=True, text=True, env=bristle_env())
    if c.returncode not in (0, 1):
        result.update(status="error", reason=f"compare exit {c.returncode}: {tail(c.stderr)}")
        return result
    try:
        metrics = json.loads(c.stdout)
    except json.JSONDecodeError:
        result.update(status="error", reason="compare --json printed no JSON: " + tail(c.stderr))
        return result
    result["metrics"] = metrics
    result["diff"] = diff_png if os.path.exists(diff_png) else None
    if c.returncode == 0:
        result.update(status="pass", reason="identical" if metrics.get("identical") else
                      "within " + g["tolerance"])
    else:
        result.update(status="fail", reason=failure_text(metrics))
    return result


def failure_text(m):
    """What broke which limit, e.g. 'max_abs 12 > 2; percent_over 0.4% > 0.1%'."""
    if "checks" not in m:
        return m.get("reason", "failed")
    unit = {"max_abs": "/255", "percent_over": "%", "psnr_db": " dB"}
    parts = []
    for k in m["checks"]:
        if k["pass"]:
            continue
        if k["metric"] == "hash":
            parts.append("pixels not identical")
            continue
        op = ">" if k["must_be"] == "<=" else "<"
        u = unit.get(k["metric"], "")
        parts.append(f"{k['metric']} {k['value']:.4g}{u} {op} {k['limit']:g}{u}")
    return "; ".join(parts)


def longest_first(goldens, work):
    """The goldens in the order to start them: slowest first (render times of the
    last run in work/summary.json; scenes first when unknown), so that two workers
    do not end with one long render alone."""
    last = {}
    try:
        with open(os.path.join(work, "summary.json"), encoding="utf-8") as f:
            last = {r["name"]: r["render_s"] for r in json.load(f)["results"]}
    except (OSError, ValueError, KeyError, TypeError):
        pass
    return sorted(goldens, key=lambda g: -last.get(g["name"], 1e6 if "scene" in g else 1e5))


def run_all(bristle, goldens, work, jobs, log=print, reuse=None):
    """reuse: (folder, {name: PNG in it}) of the goldens a batch already rendered."""
    for sub in ("new", "diff"):
        os.makedirs(os.path.join(work, sub), exist_ok=True)
    folder, pngs = reuse or ("", {})
    results = []
    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
        futures = [pool.submit(check_one, bristle, g, work,
                               os.path.join(folder, pngs[g["name"]]) if g["name"] in pngs
                               else None)
                   for g in longest_first(goldens, work)]
        for f in concurrent.futures.as_completed(futures):
            r = f.result()
            results.append(r)
            log(f"{r['status'].upper():7} {r['name']} ({r['tolerance']}, "
                f"{r['render_s']:.1f} s): {r['reason']}")
    order = {g["name"]: i for i, g in enumerate(goldens)}
    results.sort(key=lambda r: order[r["name"]])
    return results


def metric_cells(m):
    if not m or "checks" not in m:
        return "<td colspan=5></td>"
    mx = max(m["max_abs"].values())
    psnr = "inf" if m["psnr_db"] is None else f"{m['psnr_db']:.2f}"
    return (f"<td>{mx:.3g}</td><td>{m['percent_over']:.4g}%</td><td>{m['rmse']:.4g}</td>"
            f"<td>{psnr}</td><td>{m['ssim']:.6f}</td>")


def write_report(results, work, manifest, elapsed_s):
    """work/index.html: every golden's verdict; failures with reference, new and
    difference images side by side (copied next to the report)."""
    img_dir = os.path.join(work, "images")
    os.makedirs(img_dir, exist_ok=True)
    failed = [r for r in results if r["status"] != "pass"]
    rows = []
    for r in results:
        cls = "pass" if r["status"] == "pass" else "fail"
        rows.append(f"<tr class={cls}><td><a href='#{r['name']}'>{html.escape(r['name'])}</a>"
                    f"</td><td>{r['status']}</td><td>{r['tolerance']}</td>"
                    f"{metric_cells(r['metrics'])}<td>{html.escape(r['reason'])}</td></tr>")
    panels = []
    for r in failed:
        figs = []
        for label, src in (("reference (golden)", r["reference"]), ("new render", r["new"]),
                           ("difference (amplified)", r["diff"])):
            if src and os.path.exists(src):
                dest = os.path.join(img_dir, f"{r['name']}.{label.split()[0]}.png")
                shutil.copyfile(src, dest)
                rel = os.path.relpath(dest, work)
                figs.append(f"<figure><a href='{rel}'><img src='{rel}'></a>"
                            f"<figcaption>{label}</figcaption></figure>")
            else:
                figs.append(f"<figure><div class=none>no image</div>"
                            f"<figcaption>{label}</figcaption></figure>")
        panels.append(f"<section id='{r['name']}'><h2>{html.escape(r['name'])}: {r['status']}"
                      f"</h2><p>{html.escape(r['reason'])}</p><p><code>"
                      f"{html.escape(r['command'])}</code></p><div class=row>{''.join(figs)}"
                      f"</div></section>")
    page = f"""<!doctype html>
<html><head><meta charset="utf-8"><title>bristle golden report</title>
<style>
body {{ font-family: sans-serif; margin: 1.5em; }}
table {{ border-collapse: collapse; }} td, th {{ padding: 2px 8px; border-bottom: 1px solid #ddd; }}
tr.fail td {{ background: #fde8e8; }} tr.pass td:nth-child(2) {{ color: #286; }}
.row {{ display: flex; gap: 12px; }} figure {{ margin: 0; flex: 1; }}
img {{ width: 100%; image-rendering: pixelated; border: 1px solid #ccc; }}
.none {{ height: 120px; background: #eee; }}
</style></head><body>
<h1>bristle golden images: {len(failed)} of {len(results)} failed</h1>
<p>Manifest {html.escape(manifest)}; {elapsed_s:.0f} s. Metrics from <code>bristle compare
--json</code>: max abs difference and RMSE in 8-bit steps (1/255), % of pixels over the
preset's threshold, PSNR in dB, SSIM of the luma. The difference image shows differing
pixels in red (brighter for larger differences), equal pixels within 3 px of them in
yellow, and the rest as dimmed grey (docs/golden-tests.md).</p>
<table><tr><th>golden</th><th>status</th><th>tolerance</th><th>max abs</th><th>% over</th>
<th>RMSE</th><th>PSNR</th><th>SSIM</th><th>why</th></tr>
{''.join(rows)}
</table>
{''.join(panels)}
</body></html>
"""
    with open(os.path.join(work, "index.html"), "w", encoding="utf-8") as f:
        f.write(page)
    with open(os.path.join(work, "summary.json"), "w", encoding="utf-8") as f:
        json.dump({"manifest": manifest, "elapsed_s": elapsed_s,
                   "failed": [r["name"] for r in failed], "results": results}, f, indent=1)


def select(goldens, names):
    if not names:
        return goldens
    known = {g["name"] for g in goldens}
    unknown = [n for n in names if n not in known]
    if unknown:
        die(64, f"unknown golden '{unknown[0]}' (see the manifest's names)")
    return [g for g in goldens if g["name"] in names]


def main(argv=None):
    ap = argparse.ArgumentParser(prog="golden.py", description=__doc__.split("\n\n")[0])
    ap.add_argument("mode", choices=("run", "update"))
    ap.add_argument("names", nargs="*", help="only these goldens")
    ap.add_argument("--manifest", default=os.path.join(ROOT, "golden", "golden.json"))
    ap.add_argument("--bristle", default=os.path.join(ROOT, "build", "cli", "bristle"),
                    help="the bristle executable (default: build/cli/bristle)")
    ap.add_argument("--report", default=os.path.join(ROOT, "build", "golden-report"),
                    help="folder for renders, differences and index.html")
    ap.add_argument("--jobs", type=int, default=2, help="renders at a time (default 2)")
    ap.add_argument("--force", action="store_true", help="update: store every selected golden")
    ap.add_argument("--rendered-by", metavar="MANIFEST",
                    help="run: a batch manifest whose scene jobs already rendered goldens")
    ap.add_argument("--rendered", metavar="DIR", help="run: the folder that batch wrote to")
    # Intermixed: `update --force NAME...` as well as `update NAME... --force`.
    args = ap.parse_intermixed_args(argv)
    if args.jobs < 1:
        die(64, "--jobs must be at least 1")
    if args.force and args.mode != "update":
        die(64, "--force belongs to update")
    if not os.access(args.bristle, os.X_OK):
        die(66, f"{args.bristle}: no bristle executable (build it, or pass --bristle)")
    try:
        goldens = select(load_manifest(args.manifest), args.names)
    except ManifestError as e:
        die(65, str(e))
    if bool(args.rendered_by) != bool(args.rendered):
        die(64, "--rendered-by and --rendered go together")
    if args.rendered and args.mode != "run":
        die(64, "--rendered belongs to run: update renders every golden it stores")
    reuse = None
    if args.rendered:
        reuse = (os.path.abspath(args.rendered), batch_renders(args.rendered_by, goldens))
    work = os.path.abspath(args.report)

    started = time.monotonic()
    results = run_all(args.bristle, goldens, work, args.jobs, reuse=reuse)
    elapsed = time.monotonic() - started
    bad = [r for r in results if r["status"] != "pass"]

    if args.mode == "update":
        errors = [r for r in results if r["status"] == "error"]
        stored = []
        for r in results:
            if r["status"] == "error":
                continue
            if args.force or r["status"] in ("fail", "missing"):
                shutil.copyfile(r["new"], r["reference"])
                stored.append(r["name"])
        for name in stored:
            print(f"stored  {name}")
        listed = {os.path.basename(g["png"]) for g in load_manifest(args.manifest)}
        folder = os.path.dirname(os.path.abspath(args.manifest))
        for f in sorted(os.listdir(folder)):
            if f.endswith(".png") and f not in listed:
                print(f"golden: warning: {os.path.join(folder, f)} is not in the manifest",
                      file=sys.stderr)
        print(f"{len(stored)} of {len(results)} goldens stored, {len(errors)} render errors "
              f"({elapsed:.0f} s); review them (git diff --stat, the images) before committing")
        return 1 if errors else 0

    write_report(results, work, os.path.abspath(args.manifest), elapsed)
    report = os.path.join(work, "index.html")
    if bad:
        print(f"{len(bad)} of {len(results)} goldens FAILED ({elapsed:.0f} s): "
              f"{', '.join(r['name'] for r in bad)}; report: {report}")
        return 1
    print(f"all {len(results)} goldens pass ({elapsed:.0f} s); report: {report}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
