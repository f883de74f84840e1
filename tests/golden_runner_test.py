#!/usr/bin/env python3
"""The golden runner (scripts/golden.py) must fail when a golden is perturbed.

On a copy of one golden in a temporary folder: the untouched copy passes; a
copy with a 4 x 4 block of pixels off by 40/255 in red fails, names the
golden and the broken limit, and writes the new, reference and difference
images and the HTML report; `update` stores the new render and the suite
passes again, and `update --force NAME` stores a passing one; a golden of another size fails naming both sizes; a missing
golden fails; a broken manifest exits 65 naming the field. A scene golden
taken as a batch rendered it (--rendered-by, --rendered) passes as rendered,
fails perturbed, is an error when the batch left no PNG, and is rendered again
when the batch's job adds an option. Usage: golden_runner_test.py BRISTLE_EXECUTABLE
"""

import json
import os
import shutil
import struct
import subprocess
import sys
import tempfile
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
RUNNER = os.path.join(ROOT, "scripts", "golden.py")
# A small canvas (334 x 334 px) keeps each render near a second.
GOLDEN = "bright-press-lift"
# The perturbation: 40 steps, far over strict's 2-step limit, in a block
# small enough (16 px of 111556, 0.014%) to pass strict's 0.1% pixel count:
# the failure must come from max_abs alone.
OFFSET = 40
BLOCK = 4


def read_png_rgb8(path):
    """Pixels of an 8-bit RGB, non-interlaced PNG (what bristle render writes)."""
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", path
    pos, idat = 8, b""
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            w, h, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", body)
            assert (depth, colour, interlace) == (8, 2, 0), "expected 8-bit RGB"
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    raw = zlib.decompress(idat)
    stride, bpp = w * 3, 3
    rows, prev, i = [], bytearray(stride), 0
    for _ in range(h):
        f, line = raw[i], bytearray(raw[i + 1:i + 1 + stride])
        i += 1 + stride
        for x in range(stride):
            a = line[x - bpp] if x >= bpp else 0
            b = prev[x]
            c = prev[x - bpp] if x >= bpp else 0
            if f == 1:
                line[x] = (line[x] + a) & 0xFF
            elif f == 2:
                line[x] = (line[x] + b) & 0xFF
            elif f == 3:
                line[x] = (line[x] + (a + b) // 2) & 0xFF
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                line[x] = (line[x] + pred) & 0xFF
        rows.append(line)
        prev = line
    return w, h, rows


def write_png_rgb8(path, w, h, rows):
    def chunk(kind, body):
        return (struct.pack(">I", len(body)) + kind + body +
                struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF))
    raw = b"".join(b"\x00" + bytes(r) for r in rows)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(raw)))
        f.write(chunk(b"IEND", b""))


def run(*args):
    r = subprocess.run([sys.executable, RUNNER, *args], capture_output=True, text=True)
    return r.returncode, r.stdout + r.stderr


failures = []


def expect(condition, what, output=""):
    if not condition:
        failures.append(what)
        print(f"FAILED: {what}\n{output}", file=sys.stderr)


def check_batch_rendered(bristle, tmp):
    """A scene golden compared as a batch manifest's job rendered it. Nothing is
    rendered: the scene is only named (the painting's path), and the batch's PNG
    is a copy of a stroke golden."""
    scene = os.path.join(ROOT, "scenes", "paintings", "petals.json")
    gdir = os.path.join(tmp, "scene-golden")
    out = os.path.join(tmp, "batch-out")
    os.makedirs(gdir)
    os.makedirs(out)
    manifest = os.path.join(gdir, "golden.json")
    json.dump({"format": "bristle-golden/1",
               "goldens": [{"name": "petals", "scene": scene, "tolerance": "strict"}]},
              open(manifest, "w"))
    shutil.copyfile(os.path.join(ROOT, "golden", GOLDEN + ".png"),
                    os.path.join(gdir, "petals.png"))
    batch = os.path.join(tmp, "paintings.json")

    def write_batch(job):
        json.dump({"format": "bristle-batch/1", "jobs": [job]}, open(batch, "w"))

    write_batch({"id": "petals", "scene": scene})
    rendered = os.path.join(out, "petals.png")
    shutil.copyfile(os.path.join(ROOT, "golden", GOLDEN + ".png"), rendered)
    # /bin/false as bristle: a golden rendered again would fail with "render exit 1".
    common = ["--manifest", manifest, "--report", os.path.join(tmp, "report2"),
              "--rendered-by", batch, "--rendered", out]
    code, out_text = run("run", "--bristle", "/bin/false", *common)
    expect(code == 1 and "render exit" not in out_text,
           "a batch's PNG is compared, not rendered again (compare needs bristle)", out_text)
    code, out_text = run("run", "--bristle", bristle, *common)
    expect(code == 0 and "all 1 goldens pass" in out_text,
           "the batch's own render of the golden passes", out_text)
    w, h, rows = read_png_rgb8(rendered)
    rows[h // 2][3 * (w // 2)] ^= 0x80
    write_png_rgb8(rendered, w, h, rows)
    code, out_text = run("run", "--bristle", bristle, *common)
    expect(code == 1 and "FAIL    petals" in out_text, "a perturbed batch render fails", out_text)
    os.remove(rendered)
    code, out_text = run("run", "--bristle", bristle, *common)
    expect(code == 1 and "the batch did not render" in out_text,
           "a golden the batch left no PNG for is an error", out_text)
    write_batch({"id": "petals", "scene": scene, "options": {"impasto": True}})
    code, out_text = run("run", "--bristle", "/bin/false", *common)
    expect(code == 1 and "render exit 1" in out_text,
           "a job with options of its own is not the golden's command: rendered again",
           out_text)
    code, out_text = run("run", "--bristle", bristle, "--manifest", manifest,
                         "--rendered", out)
    expect(code == 64 and "go together" in out_text, "--rendered alone is refused", out_text)


def main():
    bristle = os.path.abspath(sys.argv[1])
    manifest_src = json.load(open(os.path.join(ROOT, "golden", "golden.json")))
    entry = next(g for g in manifest_src["goldens"] if g["name"] == GOLDEN)
    with tempfile.TemporaryDirectory(prefix="bristle-golden-test-") as tmp:
        gdir = os.path.join(tmp, "golden")
        os.makedirs(gdir)
        for key in ("brush", "trajectory"):  # absolute: the copy lives elsewhere
            entry[key] = os.path.normpath(os.path.join(ROOT, "golden", entry[key]))
        manifest = os.path.join(gdir, "golden.json")
        json.dump({"format": "bristle-golden/1", "goldens": [entry]}, open(manifest, "w"))
        golden_png = os.path.join(gdir, GOLDEN + ".png")
        shutil.copyfile(os.path.join(ROOT, "golden", GOLDEN + ".png"), golden_png)
        report = os.path.join(tmp, "report")
        common = ["--manifest", manifest, "--bristle", bristle, "--report", report]

        code, out = run("run", *common)
        expect(code == 0, "the untouched golden passes", out)
        expect("all 1 goldens pass" in out, "the pass is reported", out)

        w, h, rows = read_png_rgb8(golden_png)
        y0, x0 = h // 2, w // 2
        for y in range(y0, y0 + BLOCK):
            for x in range(x0, x0 + BLOCK):
                v = rows[y][3 * x]
                rows[y][3 * x] = v + OFFSET if v + OFFSET <= 255 else v - OFFSET
        write_png_rgb8(golden_png, w, h, rows)

        code, out = run("run", *common)
        expect(code == 1, "a perturbed golden fails with exit 1", out)
        expect(f"FAIL    {GOLDEN}" in out, "the failing golden is named", out)
        expect(f"max_abs {OFFSET}/255 > 2/255" in out, "the broken limit is given", out)
        expect("percent_over" not in out.split("FAIL", 1)[-1].split("\n")[0],
               "only max_abs fails (16 px are under 0.1%)", out)
        index = os.path.join(report, "index.html")
        expect(os.path.exists(index), "the HTML report is written", out)
        page = open(index).read() if os.path.exists(index) else ""
        expect("1 of 1 failed" in page and GOLDEN in page, "the report names the failure")
        for kind in ("reference", "new", "difference"):
            img = os.path.join(report, "images", f"{GOLDEN}.{kind}.png")
            expect(os.path.exists(img), f"the report has the {kind} image")
        summary = json.load(open(os.path.join(report, "summary.json")))
        expect(summary["failed"] == [GOLDEN], "summary.json lists the failure")
        diff_png = os.path.join(report, "diff", GOLDEN + ".png")
        if os.path.exists(diff_png):
            _, _, drows = read_png_rgb8(diff_png)
            r, g, b = drows[y0][3 * x0:3 * x0 + 3]
            expect(r >= 64 and g == 0 and b == 0, "the difference image marks the block red")
            r, g, b = drows[0][0:3]
            expect(r == g == b, "the difference image is grey where nothing changed")
        else:
            expect(False, "the difference image is written")

        code, out = run("update", *common)
        expect(code == 0 and f"stored  {GOLDEN}" in out, "update stores the failing golden", out)
        code, out = run("run", *common)
        expect(code == 0, "after the update the suite passes", out)
        code, out = run("update", *common)
        expect(code == 0 and "stored" not in out.replace("goldens stored", ""),
               "update leaves passing goldens alone", out)
        # --force before the names, as scripts/update-goldens' help shows it.
        code, out = run("update", "--force", GOLDEN, *common)
        expect(code == 0 and f"stored  {GOLDEN}" in out,
               "update --force NAME stores that golden though it passes", out)

        # A golden of another size (one column cropped) fails and says so.
        w, h, rows = read_png_rgb8(golden_png)
        write_png_rgb8(golden_png, w - 1, h, [r[:3 * (w - 1)] for r in rows])
        code, out = run("run", *common)
        expect(code == 1 and "differ in size" in out and f"{w - 1}x{h}" in out,
               "a golden of another size fails naming both sizes", out)

        os.remove(golden_png)
        code, out = run("run", *common)
        expect(code == 1 and f"MISSING {GOLDEN}" in out, "a missing golden fails", out)

        json.dump({"format": "bristle-golden/1", "goldens": [dict(entry, tolerance="fuzzy")]},
                  open(manifest, "w"))
        code, out = run("run", *common)
        expect(code == 65 and "/goldens/0/tolerance" in out,
               "a bad manifest exits 65 naming the field", out)
        json.dump({"format": "bristle-golden/1", "goldens": [entry]}, open(manifest, "w"))
        code, out = run("run", "no-such-golden", *common)
        expect(code == 64 and "no-such-golden" in out, "an unknown name is refused", out)

        check_batch_rendered(bristle, tmp)

    if failures:
        print(f"{len(failures)} checks failed", file=sys.stderr)
        return 1
    print("golden runner: all checks pass")
    return 0


if __name__ == "__main__":
    sys.exit(main())
