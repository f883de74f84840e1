#!/usr/bin/env python3
"""The catalogue of hostile and absurd inputs (docs/errors.md).

Each case builds its inputs in a fresh folder, runs the built bristle there on
them (so messages name short relative paths), and checks:
  - the exit code;
  - stderr is exactly one line, the catalogue's message (which names the file,
    the field and the rule);
  - the folder holds exactly what it held before, byte for byte: no output, no
    temporary file, and every input and pre-existing output unchanged.

  catalogue.py --list                  the case ids (CMake registers one ctest test each)
  catalogue.py --bristle BIN ID...     runs cases
  catalogue.py --markdown              the table of docs/errors.md
  catalogue.py --check-doc FILE        FILE's table is the catalogue's
"""

import argparse
import json
import os
import shutil
import stat
import subprocess
import sys
import tempfile
from pathlib import Path

SRC = Path(__file__).resolve().parents[2]
ROUND = SRC / "scenes/brushes/round.json"
S_CURVE = SRC / "scenes/trajectories/s-curve.csv"
HEADER = "t_s,x_mm,y_mm,z_mm,qw,qx,qy,qz"
# A hang is a failure, not a measurement: no case comes near this.
HANG_GUARD_S = 120

CASES = []


def case(cid, what, args, code, message, setup=None, logs=None, env=None, fsize=None):
    """Registers a case: `bristle ARGS` in a folder set up by setup(dir) exits
    with `code` and prints `bristle: message` alone on stderr. `logs` names the
    one folder the run may add files to (a batch's job log, OUT/logs). `env`
    sets environment variables for the run (None: unset). `fsize` limits the
    size of any file the run writes (RLIMIT_FSIZE, SIGXFSZ ignored), so that a
    write past it fails as on a full disk. In the message,
    {src} stands for the source tree and {prefix} for the folder above the
    executable's (the build tree, or an install's prefix)."""
    assert not any(c.id == cid for c in CASES), cid
    CASES.append(argparse.Namespace(id=cid, what=what, args=args, code=code,
                                    message=message, setup=setup or (lambda d: None),
                                    logs=logs, env=env or {}, fsize=fsize))


# ---- inputs ---------------------------------------------------------------

def write(d, name, text):
    (d / name).write_text(text)


def brush_doc():
    return json.loads(ROUND.read_text())


def brush(name="b.json", edit=None, text=None):
    """A setup step: the round brush, edited by edit(doc), or raw text."""
    def step(d):
        if text is not None:
            write(d, name, text)
            return
        doc = brush_doc()
        if edit:
            edit(doc)
        write(d, name, json.dumps(doc, indent=1))
    return step


def trajectory(name="t.csv", rows=None, text=None):
    """A setup step: the S-curve, or rows (lists of 8 values) after the header."""
    def step(d):
        if text is not None:
            write(d, name, text)
        elif rows is None:
            shutil.copy(S_CURVE, d / name)
        else:
            write(d, name, "# bristle-trajectory/1\n" + HEADER + "\n" +
                  "".join(",".join(str(v) for v in r) + "\n" for r in rows))
    return step


def fnv1a64(data):
    h = 0xcbf29ce484222325
    for c in data:
        h = ((h ^ c) * 0x100000001b3) & 0xFFFFFFFFFFFFFFFF
    return f"{h:016x}"


def session(name="r.csv", rows=()):
    """A setup step: a recorded session of b.json (written first) with rows."""
    def step(d):
        write(d, name, "# bristle-trajectory/1\n# bristle record: a live session\n"
              f"# brush_fnv1a64: {fnv1a64((d / 'b.json').read_bytes())}\n" + HEADER + "\n" +
              "".join(",".join(str(v) for v in r) + "\n" for r in rows))
    return step


def scene(name="s.json", edit=None, text=None):
    """A setup step: a one-stroke scene of b.json along t.csv."""
    def step(d):
        if text is not None:
            write(d, name, text)
            return
        doc = {"format": "bristle-scene/1", "name": "hostile",
               "canvas": {"size_mm": [120, 90], "px_per_mm": 4},
               "strokes": [{"brush": "b.json", "trajectory": "t.csv",
                            "paint": {"paints": ["sumi-ink"]}}]}
        if edit:
            edit(doc)
        write(d, name, json.dumps(doc, indent=1))
    return step


def sheet(name="sh.json", edit=None, text=None):
    def step(d):
        if text is not None:
            write(d, name, text)
            return
        doc = {"format": "bristle-sheet/1", "name": "hostile", "brushes": ["b.json"],
               "trajectories": ["t.csv"]}
        if edit:
            edit(doc)
        write(d, name, json.dumps(doc, indent=1))
    return step


def manifest(name="m.json", edit=None, text=None):
    def step(d):
        if text is not None:
            write(d, name, text)
            return
        doc = {"format": "bristle-batch/1",
               "jobs": [{"id": "one", "brush": "b.json", "trajectory": "t.csv"}]}
        if edit:
            edit(doc)
        write(d, name, json.dumps(doc, indent=1))
    return step


def fifo(name):
    return lambda d: os.mkfifo(d / name)


def folder(name):
    return lambda d: (d / name).mkdir()


def symlink(name, target):
    return lambda d: os.symlink(target, d / name)


def sparse(name, size):
    """A file of `size` bytes that occupies no disk blocks."""
    def step(d):
        with open(d / name, "wb") as f:
            f.truncate(size)
    return step


def copy(src, name):
    return lambda d: shutil.copy(SRC / src, d / name)


def png_header(name, width, height):
    """A setup step: a small PNG whose header claims width x height RGB pixels (a
    decompression bomb's header, with one tiny IDAT)."""
    import struct
    import zlib

    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data +
                struct.pack(">I", zlib.crc32(kind + data) & 0xffffffff))

    def step(d):
        ihdr = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
        (d / name).write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) +
                               chunk(b"IDAT", zlib.compress(b"\0" * 64)) + chunk(b"IEND", b""))
    return step


def truncated(src, name, keep):
    def step(d):
        (d / name).write_bytes((SRC / src).read_bytes()[:keep])
    return step


def all_of(*steps):
    def step(d):
        for s in steps:
            s(d)
    return step


STROKE = all_of(brush(), trajectory())


def deep(n, inner="1"):
    return "[" * n + inner + "]" * n


def render(brush_path="b.json", traj="t.csv", out="o.png", *more):
    return ["render", "--brush", brush_path, "--trajectory", traj, "-o", out, *more]


# ---- running ---------------------------------------------------------------

def snapshot(d):
    """Every entry under d: its kind and, for a regular file, its bytes."""
    state = {}
    for root, dirs, files in os.walk(d):
        for name in dirs + files:
            p = Path(root) / name
            rel = str(p.relative_to(d))
            st = os.lstat(p)
            if stat.S_ISLNK(st.st_mode):
                state[rel] = ("symlink", os.readlink(p))
            elif stat.S_ISREG(st.st_mode) and st.st_size > (16 << 20):
                # Sparse stand-ins for huge files: unchanged when their size,
                # inode and modification time are.
                state[rel] = ("file", (st.st_size, st.st_ino, st.st_mtime_ns))
            elif stat.S_ISREG(st.st_mode):
                state[rel] = ("file", p.read_bytes())
            elif stat.S_ISDIR(st.st_mode):
                state[rel] = ("dir", None)
            else:
                state[rel] = ("special", stat.S_IFMT(st.st_mode))
    return state


def file_size_limit(size):
    """A preexec_fn: writes past `size` bytes fail with EFBIG (None: no limit)."""
    if size is None:
        return None

    def limit():
        import resource
        import signal
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        hard = resource.getrlimit(resource.RLIMIT_FSIZE)[1]
        resource.setrlimit(resource.RLIMIT_FSIZE, (size, hard))
    return limit


def run_case(bristle, c):
    problems = []
    with tempfile.TemporaryDirectory(prefix="bristle-hostile-") as tmp:
        d = Path(tmp)
        c.setup(d)
        before = snapshot(d)
        env = dict(os.environ)
        env.pop("GALLIUM_DRIVER", None)
        for key, value in c.env.items():
            if value is None:
                env.pop(key, None)
            else:
                env[key] = value
        try:
            r = subprocess.run([bristle, *c.args], cwd=d, env=env, stdin=subprocess.DEVNULL,
                               capture_output=True, timeout=HANG_GUARD_S,
                               preexec_fn=file_size_limit(c.fsize))
        except subprocess.TimeoutExpired:
            return [f"still running after {HANG_GUARD_S} s (a hang)"]
        err = r.stderr.decode(errors="replace")
        if os.environ.get("HOSTILE_SHOW"):
            print(f"  [{r.returncode}] {err!r}")
        prefix = Path(bristle).resolve().parent.parent
        expected = ("bristle: " + c.message.replace("{src}", str(SRC))
                    .replace("{prefix}", str(prefix)) + "\n")
        if r.returncode != c.code:
            problems.append(f"exit code {r.returncode}, expected {c.code}")
        if err != expected:
            problems.append(f"stderr was\n  {err!r}\nexpected\n  {expected!r}")
        after = snapshot(d)
        for name in sorted(set(before) | set(after)):
            if name not in after:
                problems.append(f"{name} was removed")
            elif name not in before:
                if not (c.logs and (name == c.logs or name.startswith(c.logs + "/"))):
                    problems.append(f"{name} was left behind")
            elif before[name] != after[name]:
                problems.append(f"{name} was changed")
    return problems


def markdown():
    def cell(s):
        return s.replace("|", "\\|")
    lines = ["| case | input | command | exit | message (after `bristle: `) |",
             "|---|---|---|---|---|"]
    for c in CASES:
        lines.append(f"| `{c.id}` | {cell(c.what)} | `bristle {cell(' '.join(c.args))}` | "
                     f"{c.code} | `{cell(c.message)}` |")
    return "\n".join(lines) + "\n"


BEGIN, END = "<!-- catalogue: begin -->\n", "<!-- catalogue: end -->\n"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--list", action="store_true")
    ap.add_argument("--markdown", action="store_true")
    ap.add_argument("--check-doc")
    ap.add_argument("--bristle")
    ap.add_argument("ids", nargs="*")
    a = ap.parse_args()
    if a.list:
        print(";".join(c.id for c in CASES))
        return 0
    if a.markdown:
        sys.stdout.write(markdown())
        return 0
    if a.check_doc:
        text = Path(a.check_doc).read_text()
        if BEGIN not in text or END not in text:
            print(f"{a.check_doc}: no catalogue markers")
            return 1
        table = text[text.index(BEGIN) + len(BEGIN):text.index(END)]
        if table != markdown():
            print(f"{a.check_doc}: the table is not the catalogue's; regenerate it with "
                  "tests/hostile/catalogue.py --markdown")
            return 1
        return 0
    by_id = {c.id: c for c in CASES}
    failed = 0
    for cid in a.ids or list(by_id):
        problems = run_case(a.bristle, by_id[cid])
        print(f"{cid}: {'ok' if not problems else 'FAIL'}")
        for p in problems:
            print("  " + p)
        failed += bool(problems)
    return 1 if failed else 0


# ---- the catalogue ---------------------------------------------------------
# Cases are grouped as docs/errors.md is. Each message is the whole line.


# -- deep nesting: refused while parsing, before anything walks the document --
DEEP = 100000


def deep_brush_name(d):
    doc = json.dumps(brush_doc(), indent=1).replace('"name": "round"', '"name": ' + deep(DEEP), 1)
    write(d, "b.json", doc)


def deep_key(file_step, key, text_of):
    """file_step's document with key's value replaced by 100,000 nested arrays."""
    def step(d):
        file_step(d)
        name = text_of
        doc = json.loads((d / name).read_text())
        doc[key] = "@@DEEP@@"
        write(d, name, json.dumps(doc).replace('"@@DEEP@@"', deep(DEEP)))
    return step


DEEP_MSG = "arrays and objects nest deeper than the limit of 64 levels"
KNOWN_FORMATS = ("known: bristle-brush/1, bristle-scene/1, bristle-sheet/1, bristle-batch/1, "
                 "bristle-golden/1; a trajectory is a bristle-trajectory/1 CSV")
case("deep-brush-name-validate", "a brush whose `name` is 100,000 nested arrays",
     ["validate", "b.json"], 65, "b.json: line 3, column 73: " + DEEP_MSG,
     deep_brush_name)
case("deep-brush-name-render", "the same brush, rendered", render(), 65,
     "b.json: line 3, column 73: " + DEEP_MSG, all_of(deep_brush_name, trajectory()))
case("deep-brush-objects", "a brush that is 100,000 nested objects",
     ["validate", "b.json"], 65, "b.json: line 1, column 321: " + DEEP_MSG,
     brush(text='{"a":' * DEEP + "1" + "}" * DEEP))
case("deep-brush-65-levels", "a brush nested 65 levels deep (one more than the limit)",
     ["validate", "b.json"], 65, "b.json: line 1, column 65: " + DEEP_MSG,
     brush(text=deep(65)))
case("deep-brush-64-levels", "a brush nested 64 levels deep: within the limit, refused for "
     "what it is", ["validate", "b.json"], 65, "b.json: /: must be a JSON object whose "
     "\"format\" names its kind (" + KNOWN_FORMATS + ")", brush(text=deep(64)))
case("deep-brackets-in-strings", "a brush with a key whose value is a string of 100,000 `[`: "
     "not nesting", ["validate", "b.json"], 65, "b.json: /x: unknown key 'x'",
     brush(edit=lambda b: b.update(x="[" * DEEP)))
case("deep-scene-name", "a scene whose `name` is 100,000 nested arrays",
     ["validate", "s.json"], 65, "s.json: line 1, column 102: " + DEEP_MSG,
     all_of(STROKE, deep_key(scene(), "name", "s.json")))
case("deep-scene-render", "the same scene, rendered", ["render", "s.json", "-o", "o.png"], 65,
     "s.json: line 1, column 102: " + DEEP_MSG,
     all_of(STROKE, deep_key(scene(), "name", "s.json")))
case("deep-sheet-name", "a sheet whose `name` is 100,000 nested arrays",
     ["sheet", "sh.json", "-o", "o.png"], 65, "sh.json: line 1, column 102: " + DEEP_MSG,
     all_of(STROKE, deep_key(sheet(), "name", "sh.json")))
case("deep-manifest-format", "a batch manifest whose `format` is 100,000 nested arrays",
     ["batch", "m.json", "--out", "out"], 65, "m.json: line 1, column 75: " + DEEP_MSG,
     all_of(STROKE, folder("out"), deep_key(manifest(), "format", "m.json")))
case("deep-manifest-validate-trailing", "a brush of 100,000 `[` never closed",
     ["validate", "b.json"], 65, "b.json: line 1, column 65: " + DEEP_MSG,
     brush(text="[" * DEEP))

# -- inputs are regular files, no larger than 256 MiB --------------------------
NOT_REG = "; an input must be a regular file"
case("fifo-brush", "a FIFO with no writer as the brush", render(), 66,
     "b.json: cannot read: is a FIFO" + NOT_REG, all_of(fifo("b.json"), trajectory()))
case("fifo-trajectory", "a FIFO as the trajectory", render(), 66,
     "t.csv: cannot read: is a FIFO" + NOT_REG, all_of(brush(), fifo("t.csv")))
case("fifo-validate-brush", "a FIFO given to validate", ["validate", "b.json"], 66,
     "b.json: cannot read: is a FIFO" + NOT_REG, fifo("b.json"))
case("fifo-validate-csv", "a FIFO given to validate as a trajectory", ["validate", "t.csv"],
     66, "t.csv: cannot read: is a FIFO" + NOT_REG, fifo("t.csv"))
case("fifo-scene", "a FIFO as the scene", ["render", "s.json", "-o", "o.png"], 66,
     "s.json: cannot read: is a FIFO" + NOT_REG, fifo("s.json"))
case("fifo-scene-stroke-brush", "a scene stroke whose brush is a FIFO",
     ["render", "s.json", "-o", "o.png"], 66,
     "s.json: /strokes/0/brush: cannot read 'b.json': is a FIFO" + NOT_REG,
     all_of(fifo("b.json"), trajectory(), scene()))
case("fifo-scene-stroke-trajectory", "a scene stroke whose trajectory is a FIFO",
     ["validate", "s.json"], 66,
     "s.json: /strokes/0/trajectory: cannot read 't.csv': is a FIFO" + NOT_REG,
     all_of(brush(), fifo("t.csv"), scene()))
case("fifo-sheet", "a FIFO as the sheet", ["sheet", "sh.json", "-o", "o.png"], 66,
     "sh.json: cannot read: is a FIFO" + NOT_REG, fifo("sh.json"))
case("fifo-sheet-trajectory", "a sheet listing a FIFO as a trajectory",
     ["sheet", "sh.json", "-o", "o.png"], 66,
     "sh.json: /trajectories/0: cannot read 't.csv': is a FIFO" + NOT_REG,
     all_of(brush(), fifo("t.csv"), sheet()))
case("fifo-manifest", "a FIFO as the batch manifest", ["batch", "m.json", "--out", "out"], 66,
     "m.json: cannot read: is a FIFO" + NOT_REG, all_of(folder("out"), fifo("m.json")))
case("fifo-session", "a FIFO as the session to replay",
     ["replay", "r.csv", "--brush", "b.json", "-o", "o.png"], 66,
     "r.csv: cannot read: is a FIFO" + NOT_REG, all_of(brush(), fifo("r.csv")))
case("fifo-record-trajectory", "a FIFO as the trajectory `record --device none` plays",
     ["record", "--device", "none", "--brush", "b.json", "--trajectory", "t.csv", "-o", "r.csv"],
     66, "t.csv: cannot read: is a FIFO" + NOT_REG, all_of(brush(), fifo("t.csv")))
case("fifo-png", "a FIFO as an image to compare", ["compare", "a.png", "b.png"], 66,
     "a.png: cannot read: is a FIFO" + NOT_REG,
     all_of(fifo("a.png"), copy("golden/round-s-curve.png", "b.png")))
case("devzero-brush", "/dev/zero as the brush", render("/dev/zero"), 66,
     "/dev/zero: cannot read: is a character device" + NOT_REG, trajectory())
case("devzero-trajectory", "/dev/zero as the trajectory", render("b.json", "/dev/zero"), 66,
     "/dev/zero: cannot read: is a character device" + NOT_REG, brush())
case("devzero-png", "/dev/zero as an image to compare", ["compare", "/dev/zero", "b.png"], 66,
     "/dev/zero: cannot read: is a character device" + NOT_REG,
     copy("golden/round-s-curve.png", "b.png"))
case("devnull-validate", "/dev/null given to validate", ["validate", "/dev/null"], 66,
     "/dev/null: cannot read: is a character device" + NOT_REG)
case("symlink-to-devzero", "a symlink to /dev/zero as the brush", render("z.json"), 66,
     "z.json: cannot read: is a character device" + NOT_REG,
     all_of(symlink("z.json", "/dev/zero"), trajectory()))
case("dir-brush", "a directory as the brush", render("d.json"), 66,
     "d.json: cannot read: is a directory", all_of(folder("d.json"), trajectory()))
case("dir-trajectory", "a directory as the trajectory", render("b.json", "d.csv"), 66,
     "d.csv: cannot read: is a directory", all_of(brush(), folder("d.csv")))
case("dir-png", "a directory as an image to compare", ["compare", "d.png", "b.png"], 66,
     "d.png: cannot read: is a directory",
     all_of(folder("d.png"), copy("golden/round-s-curve.png", "b.png")))
case("dir-manifest", "a directory as the batch manifest", ["batch", "m", "--out", "out"], 66,
     "m: cannot read: is a directory", all_of(folder("m"), folder("out")))
case("missing-brush", "a brush that does not exist", render("none.json"), 66,
     "none.json: cannot read: No such file or directory", trajectory())
SIZE = "bytes is over the input limit of 268435456 bytes (256 MiB)"
case("huge-brush", "a sparse brush of 256 MiB + 1 byte", ["validate", "b.json"], 65,
     "b.json: size: 268435457 " + SIZE, sparse("b.json", (256 << 20) + 1))
case("huge-trajectory", "a sparse trajectory of 1 TiB", render(), 65,
     "t.csv: size: 1099511627776 " + SIZE, all_of(brush(), sparse("t.csv", 1 << 40)))
case("huge-scene", "a sparse scene of 300 MB", ["render", "s.json", "-o", "o.png"], 65,
     "s.json: size: 300000000 " + SIZE, sparse("s.json", 300_000_000))
case("huge-session", "a sparse session of 1 GB",
     ["replay", "r.csv", "--brush", "b.json", "-o", "o.png"], 65,
     "r.csv: size: 1000000000 " + SIZE, all_of(brush(), sparse("r.csv", 1_000_000_000)))
case("huge-png", "a sparse PNG of 1 GB", ["compare", "a.png", "b.png"], 65,
     "a.png: size: 1000000000 " + SIZE,
     all_of(sparse("a.png", 1_000_000_000), copy("golden/round-s-curve.png", "b.png")))
case("empty-brush", "an empty brush file", ["validate", "b.json"], 65,
     "b.json: line 1, column 1: malformed JSON (syntax error while parsing value - unexpected "
     "end of input; expected '[', '{', or a literal)", brush(text=""))

# -- absurd but finite values: limits checked before anything is allocated ----
REST = [0.976296, -0.169359, 0.134772, 0.0]   # the S-curve's first attitude


def rows(*positions, t=None, q=REST):
    """Trajectory rows at (x, y, z) positions, 1 s apart unless t lists the times."""
    t = t or list(range(len(positions)))
    return [[t[i], *p, *q] for i, p in enumerate(positions)]


HIGH = (15, 40, 25)
case("traj-x-1e308", "a trajectory with x = 1e308", render(), 65,
     "t.csv: line 3, column 2 (x_mm): x_mm = 1e+308 is outside the limit of +-100000 mm",
     all_of(brush(), trajectory(rows=[[0, 1e308, 40, 25, *REST], [1, 15, 40, 25, *REST]])))
case("traj-y-minus-1e6", "a trajectory with y = -1e6", ["validate", "t.csv"], 65,
     "t.csv: line 4, column 3 (y_mm): y_mm = -1000000.0 is outside the limit of +-100000 mm",
     trajectory(rows=[[0, 15, 40, 25, *REST], [1, 15, -1e6, 25, *REST]]))
case("traj-z-just-over", "a trajectory with z = 100000.001", ["validate", "t.csv"], 65,
     "t.csv: line 3, column 4 (z_mm): z_mm = 100000.001 is outside the limit of +-100000 mm",
     trajectory(rows=[[0, 15, 40, 100000.001, *REST], [1, 15, 40, 25, *REST]]))
case("traj-x-at-limit", "a trajectory reaching x = 100000 mm, the limit: too large a canvas",
     render(), 65,
     "t.csv: extent: the stroke needs a 800308 x 428 px canvas, above the limit of 16384 px "
     "a side and 64 Mpx; lower --px-per-mm",
     all_of(brush(), trajectory(rows=rows(HIGH, (100000, 40, 25)))))
case("traj-quaternion-1e200", "a quaternion of 1e200", render(), 65,
     "t.csv: line 4, column 5 (qw): qw = 1e+200 is outside the limit of +-1e6 (quaternions are "
     "normalised on read)",
     all_of(brush(), trajectory(rows=[[0, *HIGH, *REST], [1, *HIGH, 1e200, 1e200, 0, 0]])))
case("traj-quaternion-minus-1e7", "a quaternion component of -1e7", ["validate", "t.csv"], 65,
     "t.csv: line 3, column 8 (qz): qz = -10000000.0 is outside the limit of +-1e6 (quaternions "
     "are normalised on read)",
     trajectory(rows=[[0, *HIGH, 1, 0, 0, -1e7], [1, *HIGH, *REST]]))
case("traj-quaternion-tiny", "a quaternion of norm 1e-200", ["validate", "t.csv"], 65,
     "t.csv: line 3: quaternion (qw,qx,qy,qz) has near-zero norm",
     trajectory(rows=[[0, *HIGH, 1e-200, 0, 0, 0], [1, *HIGH, *REST]]))
case("traj-time-1e300", "a sample at t = 1e300 s", render(), 65,
     "t.csv: line 4, column 1 (t_s): t_s = 1e300 is outside the limit of +-1e9 s",
     all_of(brush(), trajectory(rows=rows(HIGH, HIGH, t=[0, "1e300"]))))
case("traj-span-1e7", "two samples 1e7 s apart: 1.2 billion steps at 120 Hz", render(), 65,
     "t.csv: line 4, column 1 (t_s): the trajectory plans 1200000001 simulation steps up to "
     "here, over the limit of 10000000 per trajectory",
     all_of(brush(), trajectory(rows=rows(HIGH, HIGH, t=[0, 10000000]))))
case("traj-span-2e9", "two samples 2e9 s apart (the whole time range)", render(), 65,
     "t.csv: line 4, column 1 (t_s): the trajectory plans 240000000001 simulation steps up to "
     "here, over the limit of 10000000 per trajectory",
     all_of(brush(), trajectory(rows=rows(HIGH, HIGH, t=[-1000000000, 1000000000]))))
case("traj-span-over-many-rows", "a day of gesture in 25 one-hour spans: the limit is for the "
     "whole trajectory", render(), 65,
     "t.csv: line 6, column 1 (t_s): the trajectory plans 10368001 simulation steps up to here, "
     "over the limit of 10000000 per trajectory",
     all_of(brush(), trajectory(rows=rows(*[HIGH] * 25, t=[3600 * 8 * i for i in range(25)]))))
case("traj-teleport", "the handle jumps 1 m in a microsecond", render(), 65,
     "t.csv: line 4, column 1 (t_s): the 1e-06 s since the previous sample plan 4000 simulation "
     "steps, over the limit of 1000000 steps per second of gesture (the handle moves 1000 mm)",
     all_of(brush(), trajectory(rows=rows(HIGH, (1015, 40, 25), t=[0, "0.000001"]))))
case("traj-t-column-named", "a long span when t_s is not the first column", render(), 65,
     "t.csv: line 4, column 3 (t_s): the trajectory plans 1200000001 simulation steps up to "
     "here, over the limit of 10000000 per trajectory",
     all_of(brush(), trajectory(text="# bristle-trajectory/1\nx_mm,y_mm,t_s,z_mm,qw,qx,qy,qz\n"
                                "15,40,0,25,1,0,0,0\n15,40,1e7,25,1,0,0,0\n")))
DEPTH_HEADER = "t_s,x_mm,y_mm,depth_mm,qw,qx,qy,qz"
case("traj-z-and-depth", "a trajectory giving both z_mm and depth_mm", ["validate", "t.csv"], 65,
     "t.csv: line 2, column 9 (depth_mm): z_mm and depth_mm both give the handle's height; "
     "give one of them",
     trajectory(text="# bristle-trajectory/1\n" + HEADER + ",depth_mm\n"
                "0,15,40,25,1,0,0,0,-2\n1,15,40,25,1,0,0,0,3\n"))
case("traj-depth-nan", "a press depth of nan", ["validate", "t.csv"], 65,
     "t.csv: line 4, column 4 (depth_mm): 'nan': must be finite",
     trajectory(text="# bristle-trajectory/1\n" + DEPTH_HEADER + "\n"
                "0,15,40,-2,1,0,0,0\n1,15,40,nan,1,0,0,0\n"))
case("traj-depth-through-ferrule", "a press depth that puts the ferrule into the paper",
     render(), 65,
     "t.csv: line 4: the ferrule goes below the canvas (spine 0 root at z = -6.658 mm); z must "
     "stay >= 0 (depth_mm = 25 presses 'round' too deep)",
     all_of(brush(), trajectory(text="# bristle-trajectory/1\n" + DEPTH_HEADER + "\n" +
                                "".join(",".join(str(v) for v in r) + "\n"
                                        for r in [[0, 15, 40, -2, *REST], [1, 15, 40, 25, *REST]]))))
case("traj-depth-starts-pressed", "a depth trajectory that starts pressed into the paper",
     ["validate", "b.json", "t.csv"], 65,
     "t.csv: line 3: the brush starts below the canvas (spine 1 joint 4 at z = -1.75 mm at rest, its lowest); "
     "start the trajectory with the hairs above z = 0 (a negative depth_mm, here 2)",
     all_of(brush(), trajectory(text="# bristle-trajectory/1\n" + DEPTH_HEADER + "\n"
                                "0,15,40,2,1,0,0,0\n1,15,40,-3,1,0,0,0\n")))
case("scene-span-1e7", "a scene stroke whose trajectory spans 1e7 s",
     ["render", "s.json", "-o", "o.png"], 65,
     "t.csv: line 4, column 1 (t_s): the trajectory plans 1200000001 simulation steps up to "
     "here, over the limit of 10000000 per trajectory",
     all_of(brush(), trajectory(rows=rows(HIGH, (15, 40, 9), t=[0, 10000000])), scene(
         edit=lambda s: s.update(sim={"rate_hz": 120}))))
case("replay-span-1e7", "a session spanning 1e7 s, replayed",
     ["replay", "r.csv", "--brush", "b.json", "-o", "o.png"], 65,
     "r.csv: line 6, column 1 (t_s): the trajectory plans 1200000001 simulation steps up to "
     "here, over the limit of 10000000 per trajectory",
     all_of(brush(), session("r.csv", rows=rows(HIGH, HIGH, t=[0, 10000000]))))


def set_spine(key, index, value):
    def edit(b):
        b["spines"][0][key][index] = value
    return edit


def set_cage(vertex, axis, value):
    def edit(b):
        b["surface"]["cage_vertices_mm"][vertex][axis] = value
    return edit


LIMIT_MM = "(the limit)"
case("brush-width-1e308", "a brush width of 1e308 mm", ["validate", "b.json"], 65,
     "b.json: /spines/0/width_mm/1 = 1e+308: must be <= 1000 mm " + LIMIT_MM,
     brush(edit=set_spine("width_mm", 1, 1e308)))
case("brush-width-render", "the same brush, rendered", render(), 65,
     "b.json: /spines/0/width_mm/1 = 1e+308: must be <= 1000 mm " + LIMIT_MM,
     all_of(brush(edit=set_spine("width_mm", 1, 1e308)), trajectory()))
case("brush-segment-1e308", "a segment 1e308 mm long", ["validate", "b.json"], 65,
     "b.json: /spines/0/segment_lengths_mm/0 = 1e+308: must be <= 1000 mm " + LIMIT_MM,
     brush(edit=set_spine("segment_lengths_mm", 0, 1e308)))
case("brush-root-x-1e308", "a spine root at x = 1e308 mm", ["validate", "b.json"], 65,
     "b.json: /spines/0/root_mm/0 = 1e+308: must be within +-1000 mm " + LIMIT_MM,
     brush(edit=set_spine("root_mm", 0, 1e308)))
case("brush-root-z-minus-2000", "a spine root 2 m below the handle", ["validate", "b.json"], 65,
     "b.json: /spines/0/root_mm/2 = -2000.0: must be within +-1000 mm " + LIMIT_MM,
     brush(edit=set_spine("root_mm", 2, -2000)))
case("brush-cage-1e308", "a cage vertex at y = 1e308 mm", ["validate", "b.json"], 65,
     "b.json: /surface/cage_vertices_mm/3 = [-0.7829,1e+308,0.0]: must be within +-1000 mm "
     + LIMIT_MM, brush(edit=set_cage(3, 1, 1e308)))
case("brush-cage-render", "the same brush, rendered", render(), 65,
     "b.json: /surface/cage_vertices_mm/3 = [-0.7829,1e+308,0.0]: must be within +-1000 mm "
     + LIMIT_MM, all_of(brush(edit=set_cage(3, 1, 1e308)), trajectory()))
case("scene-offset-1e308", "a scene placement offset of 1e308 mm", ["validate", "s.json"], 65,
     "s.json: /strokes/0/placement/offset_mm/0 = 1e+308: must be within +-100000 mm (the limit)",
     all_of(STROKE, scene(edit=lambda s: s["strokes"][0].update(
         placement={"offset_mm": [1e308, 0]}))))
case("scene-canvas-1e308", "a scene canvas 1e308 mm wide", ["validate", "s.json"], 65,
     "s.json: /canvas/size_mm: 1e+308 x 90 mm at 4 px/mm is inf x 360 px: larger than the limit of "
     "16384 px a side and 67108864 px in all",
     all_of(STROKE, scene(edit=lambda s: s["canvas"].update(size_mm=[1e308, 90]))))
case("render-offset-1e308", "`--offset-mm 1e308 0 0`", render("b.json", "t.csv", "o.png",
     "--offset-mm", "1e308", "0", "0"), 64, "--offset-mm: must be within +-100000 mm (the limit)",
     STROKE)
case("render-threads-3", "`--threads 3`: a render uses one thread or two",
     render("b.json", "t.csv", "o.png", "--threads", "3"), 64,
     "--threads: Value 3 not in range 1 to 2 (see bristle --help)", STROKE)

# -- outputs never overwrite inputs, never replace a device or a FIFO ---------
OVER = "; an output must not overwrite an input"
NOT_REG_OUT = "; an output must be a regular file"
PNG = copy("golden/round-s-curve.png", "a.png")
case("out-is-brush", "`-o` is the brush", render(out="b.json"), 64,
     "b.json: -o: is the same file as the input b.json (--brush)" + OVER, STROKE)
case("out-is-trajectory", "`-o` is the trajectory", render(out="t.csv"), 64,
     "t.csv: -o: is the same file as the input t.csv (--trajectory)" + OVER, STROKE)
case("trace-is-trajectory", "`--trace` is the trajectory", render("b.json", "t.csv", "o.png",
     "--trace", "t.csv"), 64,
     "t.csv: --trace: is the same file as the input t.csv (--trajectory)" + OVER, STROKE)
case("forces-is-brush", "`--forces` is the brush", render("b.json", "t.csv", "o.png",
     "--forces", "./b.json"), 64,
     "./b.json: --forces: is the same file as the input b.json (--brush)" + OVER, STROKE)
case("trace-is-output", "`--trace` is the `-o` PNG", render("b.json", "t.csv", "o.png",
     "--trace", "o.png"), 64,
     "o.png: --trace: is the same file as the output o.png (-o); give each output its own file",
     STROKE)
case("out-symlink-to-brush", "`-o` is a symbolic link to the brush", render(out="l.png"), 64,
     "l.png: -o: is the same file as the input b.json (--brush)" + OVER,
     all_of(STROKE, symlink("l.png", "b.json")))
case("out-hardlink-to-trajectory", "`-o` is a hard link to the trajectory",
     render(out="h.png"), 64,
     "h.png: -o: is the same file as the input t.csv (--trajectory)" + OVER,
     all_of(STROKE, lambda d: os.link(d / "t.csv", d / "h.png")))
case("out-is-devnull", "`-o /dev/null`", render(out="/dev/null"), 73,
     "/dev/null: cannot create output: is a character device" + NOT_REG_OUT, STROKE)
case("out-is-devfull", "`-o /dev/full`", render(out="/dev/full"), 73,
     "/dev/full: cannot create output: is a character device" + NOT_REG_OUT, STROKE)
case("trace-is-devstdout", "`--trace /dev/stdout` (a pipe)", render("b.json", "t.csv", "o.png",
     "--trace", "/dev/stdout"), 73,
     "/dev/stdout: cannot create output: is a FIFO" + NOT_REG_OUT, STROKE)
case("out-is-fifo", "`-o` is a FIFO", render(out="f.png"), 73,
     "f.png: cannot create output: is a FIFO" + NOT_REG_OUT, all_of(STROKE, fifo("f.png")))
case("out-is-directory", "`-o` is a directory", render(out="d.png"), 73,
     "d.png: cannot create output: is a directory" + NOT_REG_OUT, all_of(STROKE, folder("d.png")))
case("out-symlink-to-devnull", "`-o` is a symbolic link to /dev/null", render(out="n.png"), 73,
     "n.png: cannot create output: is a character device" + NOT_REG_OUT,
     all_of(STROKE, symlink("n.png", "/dev/null")))
case("scene-out-is-scene", "a scene rendered onto itself", ["render", "s.json", "-o", "s.json"],
     64, "s.json: -o: is the same file as the input s.json (scene)" + OVER, all_of(STROKE, scene()))
case("scene-out-is-brush", "a scene rendered onto its stroke's brush",
     ["render", "s.json", "-o", "b.json"], 64,
     "b.json: -o: is the same file as the input b.json (s.json: /strokes/0/brush)" + OVER,
     all_of(STROKE, scene()))
case("scene-trace-is-trajectory", "a scene's `--trace` onto its stroke's trajectory",
     ["render", "s.json", "-o", "o.png", "--trace", "t.csv"], 64,
     "t.csv: --trace: is the same file as the input t.csv (s.json: /strokes/0/trajectory)" + OVER,
     all_of(STROKE, scene()))
case("sheet-out-is-sheet", "a sheet rendered onto itself", ["sheet", "sh.json", "-o", "sh.json"],
     64, "sh.json: -o: is the same file as the input sh.json (sheet)" + OVER,
     all_of(STROKE, sheet()))
case("sheet-out-is-trajectory", "a sheet rendered onto a trajectory it lists",
     ["sheet", "sh.json", "-o", "t.csv"], 64,
     "t.csv: -o: is the same file as the input t.csv (sh.json: /trajectories/0)" + OVER,
     all_of(STROKE, sheet()))
case("preview-out-is-brush", "`preview` onto its brush", ["preview", "b.json", "-o", "b.json"],
     64, "b.json: -o: is the same file as the input b.json (brush)" + OVER, brush())
RECORD = ["record", "--device", "none", "--brush", "b.json", "--trajectory", "t.csv"]
case("record-out-is-trajectory", "`record -o` is the `--trajectory` it plays",
     RECORD + ["-o", "t.csv"], 64,
     "t.csv: -o: is the same file as the input t.csv (--trajectory)" + OVER, STROKE)
case("record-forces-is-brush", "`record --forces` is the brush",
     RECORD + ["-o", "r.csv", "--forces", "b.json"], 64,
     "b.json: --forces: is the same file as the input b.json (--brush)" + OVER, STROKE)
case("record-png-is-session", "`record --png` is the session `-o`",
     RECORD + ["-o", "r.csv", "--png", "r.csv"], 64,
     "r.csv: --png: is the same file as the output r.csv (-o); give each output its own file",
     STROKE)
case("record-forces-missing-folder", "`record --forces` in a missing folder, over an existing "
     "session: the session is not truncated", RECORD + ["-o", "r.csv", "--forces", "no/f.csv"],
     73, "no/f.csv: cannot create output: No such file or directory",
     all_of(STROKE, trajectory("r.csv")))
case("record-out-is-devfull", "`record -o /dev/full`", RECORD + ["-o", "/dev/full"], 73,
     "/dev/full: cannot create output: is a character device" + NOT_REG_OUT, STROKE)
case("replay-out-is-session", "`replay -o` is the session",
     ["replay", "r.csv", "--brush", "b.json", "-o", "r.csv"], 64,
     "r.csv: -o: is the same file as the input r.csv (session)" + OVER,
     all_of(brush(), trajectory("r.csv")))
case("compare-diff-is-reference", "`compare --diff` is the reference image",
     ["compare", "a.png", "b.png", "--diff", "a.png"], 64,
     "a.png: --diff: is the same file as the input a.png (a)" + OVER,
     all_of(PNG, copy("golden/round-s-curve.png", "b.png")))
case("compare-diff-is-second", "`compare --diff` is the second image, through `./`",
     ["compare", "a.png", "b.png", "--diff", "./b.png"], 64,
     "./b.png: --diff: is the same file as the input b.png (b)" + OVER,
     all_of(PNG, copy("golden/round-s-curve.png", "b.png")))
case("compare-diff-is-devfull", "`compare --diff /dev/full`",
     ["compare", "a.png", "b.png", "--diff", "/dev/full"], 73,
     "/dev/full: cannot create output: is a character device" + NOT_REG_OUT,
     all_of(PNG, copy("golden/round-s-curve.png", "b.png")))
case("batch-log-is-manifest", "`batch --log` is the manifest",
     ["batch", "m.json", "--out", "out", "--log", "m.json"], 64,
     "m.json: --log: is the same file as the input m.json (manifest)" + OVER,
     all_of(STROKE, folder("out"), manifest()))
case("batch-log-is-brush", "`batch --log` is a job's brush",
     ["batch", "m.json", "--out", "out", "--log", "b.json"], 64,
     "b.json: --log: is the same file as the input b.json (m.json: /jobs/0/brush)" + OVER,
     all_of(STROKE, folder("out"), manifest()))

# -- more of the same, through every command that reads the file -------------
case("deep-sheet-validate", "a sheet whose `title` is 100,000 nested arrays, validated",
     ["validate", "sh.json"], 65, "sh.json: line 1, column 172: " + DEEP_MSG,
     all_of(STROKE, deep_key(sheet(), "title", "sh.json")))
case("deep-scene-stroke-brush", "a scene whose stroke's brush is nested 100,000 deep",
     ["render", "s.json", "-o", "o.png"], 65, "b.json: line 3, column 73: " + DEEP_MSG,
     all_of(deep_brush_name, trajectory(), scene()))
case("deep-sheet-brush", "a sheet whose brush is nested 100,000 deep",
     ["sheet", "sh.json", "-o", "o.png"], 65, "b.json: line 3, column 73: " + DEEP_MSG,
     all_of(deep_brush_name, trajectory(), sheet()))
case("deep-preview-brush", "`preview` of a brush nested 100,000 deep",
     ["preview", "b.json", "-o", "o.png"], 65, "b.json: line 3, column 73: " + DEEP_MSG,
     deep_brush_name)
case("deep-replay-brush", "`replay` with a brush nested 100,000 deep",
     ["replay", "r.csv", "--brush", "b.json", "-o", "o.png"], 65,
     "b.json: line 3, column 73: " + DEEP_MSG, all_of(deep_brush_name, trajectory("r.csv")))
case("deep-record-brush", "`record` with a brush nested 100,000 deep",
     RECORD + ["-o", "r.csv"], 65, "b.json: line 3, column 73: " + DEEP_MSG,
     all_of(deep_brush_name, trajectory()))
case("fifo-preview-brush", "`preview` of a FIFO", ["preview", "b.json", "-o", "o.png"], 66,
     "b.json: cannot read: is a FIFO" + NOT_REG, fifo("b.json"))
case("fifo-preview-trajectory", "`preview --trajectory` a FIFO",
     ["preview", "b.json", "--trajectory", "t.csv", "-o", "o.png"], 66,
     "t.csv: cannot read: is a FIFO" + NOT_REG, all_of(brush(), fifo("t.csv")))
case("fifo-replay-brush", "`replay --brush` a FIFO",
     ["replay", "r.csv", "--brush", "b.json", "-o", "o.png"], 66,
     "b.json: cannot read: is a FIFO" + NOT_REG, all_of(fifo("b.json"), trajectory("r.csv")))
case("fifo-record-brush", "`record --brush` a FIFO", RECORD + ["-o", "r.csv"], 66,
     "b.json: cannot read: is a FIFO" + NOT_REG, all_of(fifo("b.json"), trajectory()))
case("fifo-sheet-brush", "a sheet listing a FIFO as a brush", ["validate", "sh.json"], 66,
     "sh.json: /brushes/0: cannot read 'b.json': is a FIFO" + NOT_REG,
     all_of(fifo("b.json"), trajectory(), sheet()))
case("fifo-manifest-brush", "a batch job whose brush is a FIFO (`--dry-run`)",
     ["batch", "m.json", "--out", "out", "--dry-run", "-q"], 66,
     "job 'one' failed (66): m.json: /jobs/0/brush: b.json: cannot read: is a FIFO" + NOT_REG,
     all_of(fifo("b.json"), trajectory(), folder("out"), manifest()))
case("devzero-scene", "/dev/zero as the scene", ["render", "/dev/zero", "-o", "o.png"], 66,
     "/dev/zero: cannot read: is a character device" + NOT_REG)
case("devzero-session", "/dev/zero as the session",
     ["replay", "/dev/zero", "--brush", "b.json", "-o", "o.png"], 66,
     "/dev/zero: cannot read: is a character device" + NOT_REG, brush())
case("devzero-manifest", "/dev/zero as the batch manifest",
     ["batch", "/dev/zero", "--out", "out"], 66,
     "/dev/zero: cannot read: is a character device" + NOT_REG, folder("out"))
case("devzero-scene-stroke", "a scene stroke whose trajectory is /dev/zero",
     ["validate", "s.json"], 66,
     "s.json: /strokes/0/trajectory: cannot read '/dev/zero': is a character device" + NOT_REG,
     all_of(brush(), scene(edit=lambda s: s["strokes"][0].update(trajectory="/dev/zero"))))
case("dir-scene-stroke-brush", "a scene stroke whose brush is a directory",
     ["validate", "s.json"], 66, "s.json: /strokes/0/brush: cannot read 'b.json': is a directory",
     all_of(folder("b.json"), trajectory(), scene()))
case("huge-scene-stroke-brush", "a scene stroke whose brush is a sparse 512 MiB file",
     ["validate", "s.json"], 65, "b.json: size: 536870912 " + SIZE,
     all_of(sparse("b.json", 512 << 20), trajectory(), scene()))
case("huge-manifest", "a sparse batch manifest of 2 GiB", ["batch", "m.json", "--out", "out"],
     65, "m.json: size: 2147483648 " + SIZE, all_of(folder("out"), sparse("m.json", 2 << 30)))
case("traj-x-nan", "a trajectory with x = nan", ["validate", "t.csv"], 65,
     "t.csv: line 3, column 2 (x_mm): 'nan': must be finite",
     trajectory(rows=[[0, "nan", 40, 25, *REST], [1, *HIGH, *REST]]))
case("traj-t-1e999", "a time of 1e999 (beyond a double)", ["validate", "t.csv"], 65,
     "t.csv: line 3, column 1 (t_s): '1e999' is outside the range of a double",
     trajectory(rows=[["1e999", *HIGH, *REST], [1, *HIGH, *REST]]))
case("brush-number-1e999", "a brush number of 1e999 (beyond a double)", ["validate", "b.json"],
     65, "b.json: line 1, column 8: number 1e999 is out of range (must be finite)",
     brush(text='{"mu": 1e999}'))

# -- control characters in the input never break the one-line message ---------
case("nul-in-csv-cell", "a NUL byte inside a trajectory number", ["validate", "t.csv"], 65,
     "t.csv: line 3, column 2 (x_mm): '1\\u00002' is not a number",
     trajectory(text="# bristle-trajectory/1\n" + HEADER + "\n0,1\x002,40,25,1,0,0,0\n"))
case("nul-in-csv-header", "a NUL byte inside a trajectory's header", ["validate", "t.csv"], 65,
     "t.csv: line 2, column 2 (x_\\u0000mm): unknown column 'x_\\u0000mm'",
     trajectory(text="# bristle-trajectory/1\nt_s,x_\x00mm,y_mm,z_mm,qw,qx,qy,qz\n"))
case("tab-in-format-line", "control characters in a trajectory's format line",
     ["validate", "t.csv"], 65,
     "t.csv: line 1: unknown format version 'bristle-trajectory/1\\u0007\\u001b[2J' (expected "
     "bristle-trajectory/1)",
     trajectory(text="# bristle-trajectory/1\x07\x1b[2J\n" + HEADER + "\n"))
case("escaped-controls-in-paint-name", "a scene's paint name holding an escaped newline and NUL",
     ["validate", "s.json"], 65,
     "s.json: /strokes/0/paint/paints/0: unknown pigment 'ink\\u000a\\u0000' (known: "
     "ultramarine, cadmium-yellow, cadmium-red, quinacridone-rose, indian-red, burnt-umber, "
     "hookers-green, phthalo-green, cerulean-blue, hansa-yellow, brilliant-orange, "
     "titanium-white, ivory-black, yellow-ochre, burnt-sienna, phthalo-blue, alizarin-crimson, "
     "viridian, sumi-ink; or a colour \"#rrggbb\")",
     all_of(STROKE, scene(edit=lambda s: s["strokes"][0].update(paint={"paints": ["ink\n\x00"]}))))

# -- PNG inputs: bombs and broken files ---------------------------------------
GOLD = "golden/round-s-curve.png"
PNG_LIMIT = "px is over the limit of 67108864 px (64 Mpx, the largest canvas bristle writes)"
case("png-bomb-16384", "a 100-byte PNG claiming 16384 x 16384 px (a decompression bomb)",
     ["compare", "a.png", "b.png"], 65, "a.png: IHDR: 16384 x 16384 " + PNG_LIMIT,
     all_of(png_header("a.png", 16384, 16384), copy(GOLD, "b.png")))
case("png-bomb-wide", "a PNG claiming 1,000,000 x 100 px", ["compare", "a.png", "b.png"], 65,
     "b.png: IHDR: 1000000 x 100 " + PNG_LIMIT,
     all_of(copy(GOLD, "a.png"), png_header("b.png", 1000000, 100)))
case("png-bomb-diff", "a bomb as the second image, with `--diff`",
     ["compare", "a.png", "b.png", "--diff", "d.png"], 65,
     "b.png: IHDR: 8193 x 8193 " + PNG_LIMIT,
     all_of(copy(GOLD, "a.png"), png_header("b.png", 8193, 8193)))


def chunk_cut_at(src, keep):
    """(type, length, bytes left) of the PNG chunk that cutting src after `keep`
    bytes cuts short: the golden image changes when the physics does, so the
    expected message is read from it rather than written down."""
    data = (SRC / src).read_bytes()
    pos = 8
    while pos + 8 <= len(data):
        length = int.from_bytes(data[pos:pos + 4], "big")
        kind = data[pos + 4:pos + 8].decode("ascii")
        if pos + 12 + length > keep:
            return kind, length, keep - pos - 8
        pos += 12 + length
    raise ValueError(f"{src}: no chunk crosses byte {keep}")


CUT = chunk_cut_at(GOLD, 3000)
case("png-truncated", "a PNG cut off half way", ["compare", "a.png", "b.png"], 65,
     f"b.png: {CUT[0]}: a chunk of {CUT[1]} bytes is longer than the {CUT[2]} bytes left in "
     "the file (corrupt or truncated PNG)",
     all_of(copy(GOLD, "a.png"), truncated(GOLD, "b.png", 3000)))
case("png-signature-only", "a PNG of its 8-byte signature alone", ["compare", "a.png", "b.png"],
     65, "a.png: corrupt or truncated PNG: Read Error",
     all_of(truncated(GOLD, "a.png", 8), copy(GOLD, "b.png")))
case("png-text", "a text file named .png", ["compare", "a.png", "b.png"], 65,
     "a.png: not a PNG file", all_of(lambda d: write(d, "a.png", "hello\n"), copy(GOLD, "b.png")))
case("png-empty", "an empty file named .png", ["compare", "a.png", "b.png"], 65,
     "a.png: not a PNG file", all_of(lambda d: write(d, "a.png", ""), copy(GOLD, "b.png")))

# -- compare --align canvas: where an image lies, from its bristle:canvas text --
def small_png(name, canvas=None, width=2, height=2):
    """A setup step: a valid white 8-bit RGB PNG, with a bristle:canvas text
    chunk holding `canvas` when given (what bristle render writes)."""
    import struct
    import zlib

    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data +
                struct.pack(">I", zlib.crc32(kind + data) & 0xffffffff))

    def step(d):
        ihdr = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
        rows = b"".join(b"\0" + b"\xff" * 3 * width for _ in range(height))
        text = chunk(b"tEXt", b"bristle:canvas\0" + canvas.encode()) if canvas else b""
        (d / name).write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + text +
                               chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))
    return step


ALIGN = ["compare", "a.png", "b.png", "--align", "canvas"]
case("compare-align-no-canvas", "`compare --align canvas` of a PNG without a bristle:canvas chunk",
     ALIGN, 65, "b.png: no bristle:canvas text chunk, which --align canvas needs (bristle "
     "render writes it for a stroke or a scene; a preview or a sheet has none)",
     all_of(copy(GOLD, "a.png"), small_png("b.png")))
case("compare-align-scales-differ", "`compare --align canvas` of renders at 8 and 6 px/mm",
     ALIGN, 65, "a.png and b.png: --align canvas: the scales differ (8 and 6 px/mm); render both "
     "at one --px-per-mm (no resampling is done)",
     all_of(copy(GOLD, "a.png"), small_png(
         "b.png", "x0_mm=0.000000 y0_mm=0.000000 px_per_mm=6.000000 width_px=2 height_px=2")))
case("compare-align-off-grid", "`compare --align canvas`: b's corner half a pixel off a's grid",
     ALIGN, 65, "a.png and b.png: --align canvas: the canvases' pixel grids do not coincide "
     "(b's corner is not a whole number of pixels from a's)",
     all_of(copy(GOLD, "a.png"), small_png(
         "b.png", "x0_mm=0.062500 y0_mm=0.000000 px_per_mm=8.000000 width_px=2 height_px=2")))
case("compare-align-canvas-junk", "`compare --align canvas`: a bristle:canvas chunk that is not "
     "the five fields", ALIGN, 65,
     'b.png: bristle:canvas "x0_mm=0 y0_mm=nan": not "x0_mm=X y0_mm=Y px_per_mm=S width_px=W '
     'height_px=H"',
     all_of(copy(GOLD, "a.png"), small_png("b.png", "x0_mm=0 y0_mm=nan")))
case("compare-align-canvas-size", "`compare --align canvas`: a bristle:canvas chunk of another "
     "size than the image", ALIGN, 65,
     "b.png: bristle:canvas: says 4x2 px, but the image is 2x2",
     all_of(copy(GOLD, "a.png"), small_png(
         "b.png", "x0_mm=0.000000 y0_mm=0.000000 px_per_mm=8.000000 width_px=4 height_px=2")))

# -- more outputs, through every command that writes -------------------------
case("preview-out-devnull", "`preview -o /dev/null`", ["preview", "b.json", "-o", "/dev/null"],
     73, "/dev/null: cannot create output: is a character device" + NOT_REG_OUT, brush())
case("replay-out-devfull", "`replay -o /dev/full`",
     ["replay", "r.csv", "--brush", "b.json", "-o", "/dev/full"], 73,
     "/dev/full: cannot create output: is a character device" + NOT_REG_OUT,
     all_of(brush(), trajectory("r.csv")))
case("sheet-out-directory", "`sheet -o` a directory", ["sheet", "sh.json", "-o", "d.png"], 73,
     "d.png: cannot create output: is a directory" + NOT_REG_OUT,
     all_of(STROKE, sheet(), folder("d.png")))
case("scene-out-fifo", "a scene rendered to a FIFO", ["render", "s.json", "-o", "f.png"], 73,
     "f.png: cannot create output: is a FIFO" + NOT_REG_OUT, all_of(STROKE, scene(), fifo("f.png")))
case("scene-trace-devfull", "a scene's `--trace /dev/full`",
     ["render", "s.json", "-o", "o.png", "--trace", "/dev/full"], 73,
     "/dev/full: cannot create output: is a character device" + NOT_REG_OUT,
     all_of(STROKE, scene()))
case("forces-is-directory", "`--forces` a directory", render("b.json", "t.csv", "o.png",
     "--forces", "d.csv"), 73, "d.csv: cannot create output: is a directory" + NOT_REG_OUT,
     all_of(STROKE, folder("d.csv")))
case("forces-is-trace", "`--forces` and `--trace` the same file", render("b.json", "t.csv",
     "o.png", "--trace", "x.jsonl", "--forces", "x.jsonl"), 64,
     "x.jsonl: --forces: is the same file as the output x.jsonl (--trace); give each output its "
     "own file", STROKE)
case("record-forces-devnull", "`record --forces /dev/null`",
     RECORD + ["-o", "r.csv", "--forces", "/dev/null"], 73,
     "/dev/null: cannot create output: is a character device" + NOT_REG_OUT, STROKE)
case("record-png-directory", "`record --png` a directory, over an existing session",
     RECORD + ["-o", "r.csv", "--png", "d.png"], 73,
     "d.png: cannot create output: is a directory" + NOT_REG_OUT,
     all_of(STROKE, trajectory("r.csv"), folder("d.png")))
case("batch-log-devfull", "`batch --log /dev/full`",
     ["batch", "m.json", "--out", "out", "--log", "/dev/full"], 73,
     "/dev/full: cannot create output: is a character device" + NOT_REG_OUT,
     all_of(STROKE, folder("out"), manifest()))
case("compare-diff-missing-folder", "`compare --diff` into a missing folder",
     ["compare", "a.png", "b.png", "--diff", "no/d.png"], 73,
     "no/d.png: cannot create output: No such file or directory",
     all_of(PNG, truncated(GOLD, "b.png", 10 ** 9)))
case("dangling-brush", "a brush that is a dangling symbolic link", render("l.json"), 66,
     "l.json: cannot read: No such file or directory",
     all_of(symlink("l.json", "gone.json"), trajectory()))

# -- the limits through every command that reads the file --------------------
FAR = all_of(brush(), trajectory(rows=[[0, 1e308, 40, 25, *REST], [1, *HIGH, *REST]]))
LONG = all_of(brush(), trajectory(rows=rows(HIGH, (15, 40, 9), t=[0, 10000000])))
case("sheet-traj-x-1e308", "a sheet listing a trajectory with x = 1e308",
     ["sheet", "sh.json", "-o", "o.png"], 65,
     "t.csv: line 3, column 2 (x_mm): x_mm = 1e+308 is outside the limit of "
     "+-100000 mm", all_of(FAR, sheet()))
case("scene-traj-quaternion-1e200", "a scene stroke along a quaternion of 1e200",
     ["validate", "s.json"], 65,
     "t.csv: line 4, column 5 (qw): qw = 1e+200 is outside the limit of "
     "+-1e6 (quaternions are normalised on read)",
     all_of(brush(), trajectory(rows=[[0, *HIGH, *REST], [1, *HIGH, 1e200, 0, 0, 0]]), scene()))
case("record-traj-x-1e308", "`record --device none` playing x = 1e308",
     RECORD + ["-o", "r.csv"], 65,
     "t.csv: line 3, column 2 (x_mm): x_mm = 1e+308 is outside the limit of "
     "+-100000 mm", FAR)
case("replay-session-quaternion-1e200", "a session with a quaternion of 1e200, replayed",
     ["replay", "r.csv", "--brush", "b.json", "-o", "o.png"], 65,
     "r.csv: line 6, column 5 (qw): qw = 1e+200 is outside the limit of "
     "+-1e6 (quaternions are normalised on read)",
     all_of(brush(), session("r.csv", rows=[[0, *HIGH, *REST], [1, *HIGH, 1e200, 0, 0, 0]])))
case("preview-offset-1e308", "`preview --offset-mm 1e308 0 0`",
     ["preview", "b.json", "--trajectory", "t.csv", "--offset-mm", "1e308", "0", "0", "-o",
      "o.png"], 64, "--offset-mm: must be within +-100000 mm (the limit)", STROKE)
case("preview-at-without-trajectory", "`preview --at` with no trajectory to go along",
     ["preview", "b.json", "--at", "1.2", "-o", "o.png"], 64,
     "--at requires --trajectory (see bristle --help)", brush())
case("preview-offset-without-trajectory", "`preview --offset-mm` with no trajectory to shift",
     ["preview", "b.json", "--offset-mm", "0", "0", "2", "-o", "o.png"], 64,
     "--offset-mm requires --trajectory (see bristle --help)", brush())
case("preview-span-1e7", "`preview` along two samples 1e7 s apart",
     ["preview", "b.json", "--trajectory", "t.csv", "--at", "1", "-o", "o.png"], 65,
     "t.csv: line 4, column 1 (t_s): the trajectory plans 1200000001 "
     "simulation steps up to here, over the limit of 10000000 per trajectory", LONG)
case("sheet-span-1e7", "a sheet whose trajectory spans 1e7 s",
     ["sheet", "sh.json", "-o", "o.png"], 65,
     "t.csv: line 4, column 1 (t_s): the trajectory plans 1200000001 "
     "simulation steps up to here, over the limit of 10000000 per trajectory",
     all_of(LONG, sheet()))
case("session-buttons-1e308", "a session whose buttons are 1e308",
     ["validate", "r.csv"], 65, "r.csv: line 3, column 9 (buttons): must be a non-negative integer "
     "bitmask",
     trajectory("r.csv", text="# bristle-trajectory/1\n" + HEADER + ",buttons\n"
                "0,15,40,25,1,0,0,0,1e308\n1,15,40,25,1,0,0,0,0\n"))
case("scene-rotate-1e308", "a scene stroke rotated by 1e308 degrees", ["validate", "s.json"],
     65, "s.json: /strokes/0/placement/rotate_deg = 1e+308: must be within "
     "+-3600 degrees", all_of(STROKE, scene(edit=lambda s: s["strokes"][0].update(
         placement={"rotate_deg": 1e308}))))
case("scene-px-per-mm-1e308", "a scene canvas at 1e308 px/mm", ["validate", "s.json"], 65,
     "s.json: /canvas/px_per_mm = 1e+308: must be in (0, 100]",
     all_of(STROKE, scene(edit=lambda s: s["canvas"].update(px_per_mm=1e308))))
case("scene-rate-1e308", "a scene simulated at 1e308 Hz", ["validate", "s.json"], 65,
     "s.json: /sim/rate_hz = 1e+308: must be in [1, 10000] steps per second",
     all_of(STROKE, scene(edit=lambda s: s.update(sim={"rate_hz": 1e308}))))
case("sheet-px-per-mm-1e308", "a sheet at 1e308 px/mm", ["validate", "sh.json"], 65,
     "sh.json: /px_per_mm = 1e+308: must be in (0, 100]",
     all_of(STROKE, sheet(edit=lambda s: s.update(px_per_mm=1e308))))

case("fifo-in-brush-library", "a FIFO among the brushes of `brushes --library`",
     ["brushes", "--library", "lib"], 66,
     "lib/zz.json: cannot read: is a FIFO" + NOT_REG,
     all_of(folder("lib"), copy("scenes/brushes/round.json", "lib/round.json"),
            fifo("lib/zz.json")))

# -- batch manifests: outputs stay beneath --out, options are typed -----------
BATCH_DRY = ["batch", "m.json", "--out", "out", "--dry-run", "-q"]
BATCH_RUN = ["batch", "m.json", "--out", "out", "-q"]
BENEATH = "; a batch writes only beneath --out"


def job_edit(**keys):
    return lambda m: m["jobs"][0].update(keys)


def job_options(options):
    return manifest(edit=job_edit(options=options))


case("batch-out-symlink-folder", "a job's output through a symbolic link in `--out` to a folder "
     "outside it", BATCH_DRY, 73,
     "job 'one' failed (73): out/sub/x.png: cannot create output: out/sub is a symbolic link"
     + BENEATH,
     all_of(STROKE, folder("out"), folder("elsewhere"), symlink("out/sub", "../elsewhere"),
            manifest(edit=job_edit(output="sub/x.png"))))
case("batch-out-symlink-folder-render", "the same, rendered: nothing is written outside `--out`",
     BATCH_RUN, 73,
     "job 'one' failed (73): out/sub/x.png: cannot create output: out/sub is a symbolic link"
     + BENEATH,
     all_of(STROKE, folder("out"), folder("elsewhere"), symlink("out/sub", "../elsewhere"),
            manifest(edit=job_edit(output="sub/x.png"))), logs="out/logs")
case("batch-out-symlink-deep", "a symbolic link two folders down in `--out`",
     BATCH_RUN, 73,
     "job 'one' failed (73): out/a/b/x.png: cannot create output: out/a/b is a symbolic link"
     + BENEATH,
     all_of(STROKE, folder("out"), folder("out/a"), folder("elsewhere"),
            symlink("out/a/b", "../../elsewhere"), manifest(edit=job_edit(output="a/b/x.png"))),
     logs="out/logs")
case("batch-out-symlink-file", "a job's output is a symbolic link to a file outside `--out`",
     BATCH_RUN, 73,
     "job 'one' failed (73): out/x.png: cannot create output: is a symbolic link" + BENEATH,
     all_of(STROKE, folder("out"), copy("fuzz/seeds/png/rgb8.png", "victim.png"),
            symlink("out/x.png", "../victim.png"), manifest(edit=job_edit(output="x.png"))),
     logs="out/logs")
case("batch-logs-symlink", "`--out`'s job-log folder is a symbolic link to a folder outside it",
     BATCH_RUN, 73,
     "out/logs: cannot create: is a symbolic link" + BENEATH,
     all_of(STROKE, folder("out"), folder("elsewhere"), symlink("out/logs", "../elsewhere"),
            manifest()))
case("batch-option-smuggles-trace", "an option's list smuggling `--trace` into the job",
     BATCH_DRY, 65,
     'm.json: /jobs/0/options/offset-mm = [1,"--trace","/tmp/elsewhere.jsonl"]: must be a list '
     "of three numbers", all_of(STROKE, folder("out"),
                                job_options({"offset-mm": [1, "--trace", "/tmp/elsewhere.jsonl"]})))
case("batch-option-string-is-flag", "a string option's value that reads as an option",
     BATCH_DRY, 65,
     'm.json: /jobs/0/options/paint = "--trace=/x": must be a non-empty string that does not '
     "start with '-' and holds no control character",
     all_of(STROKE, folder("out"), job_options({"paint": "--trace=/x"})))
case("batch-option-newline", "an option's value holding a newline and a fake message",
     BATCH_DRY, 65,
     'm.json: /jobs/0/options/paint = "red\\nbristle: fake": must be a non-empty string that '
     "does not start with '-' and holds no control character",
     all_of(STROKE, folder("out"), job_options({"paint": "red\nbristle: fake"})))
case("batch-option-unknown", "an option no job command has", BATCH_DRY, 65,
     "m.json: /jobs/0/options/frobnicate: unknown option 'frobnicate' (known: amount, at, "
     "background, bits, color, colour, contact-band-mm, height, impasto, ipopt-option, load, "
     "max-step-mm, min-rate-hz, mix, offset-mm, paint, paper-scale, paper-seed, paper-tooth, "
     "px-per-mm, solver, solver-max-iterations, steady-step-mm, tip-length, width)",
     all_of(STROKE, folder("out"), job_options({"frobnicate": 1})))
case("batch-defaults-option-unknown", "an unknown option in the manifest's defaults",
     BATCH_DRY, 65,
     "m.json: /defaults/options/quiet-paper: unknown option 'quiet-paper' (known: amount, at, "
     "background, bits, color, colour, contact-band-mm, height, impasto, ipopt-option, load, "
     "max-step-mm, min-rate-hz, mix, offset-mm, paint, paper-scale, paper-seed, paper-tooth, "
     "px-per-mm, solver, solver-max-iterations, steady-step-mm, tip-length, width)",
     all_of(STROKE, folder("out"),
            manifest(edit=lambda m: m.update(defaults={"options": {"quiet-paper": False}}))))
case("batch-option-flag-not-bool", "a flag given a number", BATCH_DRY, 65,
     "m.json: /jobs/0/options/impasto = 1: must be true or false (a flag)",
     all_of(STROKE, folder("out"), job_options({"impasto": 1})))
case("batch-option-number-as-string", "a number option given a string", BATCH_DRY, 65,
     'm.json: /jobs/0/options/px-per-mm = "8": must be a number',
     all_of(STROKE, folder("out"), job_options({"px-per-mm": "8"})))
case("batch-option-reserved", "`trace` set as a job option", BATCH_DRY, 65,
     "m.json: /jobs/0/options/trace: a batch job cannot set --trace (the batch chooses the "
     "output and writes only PNGs)",
     all_of(STROKE, folder("out"), job_options({"trace": "t.jsonl"})))
case("batch-id-control", "a job id holding an escape sequence", BATCH_DRY, 65,
     'm.json: /jobs/0/id = "one\\u001b[2J": must hold no control character',
     all_of(STROKE, folder("out"), manifest(edit=job_edit(id="one\x1b[2J"))))

# -- record --device none plans the trajectory it plays ------------------------
case("record-span-1e7", "`record --device none` playing two samples 1e7 s apart",
     RECORD + ["-o", "r.csv"], 65,
     "t.csv: line 4, column 1 (t_s): the trajectory plans 1200000001 "
     "simulation steps up to here, over the limit of 10000000 per trajectory", LONG)
case("record-teleport", "`record --device none` playing a jump of 1 m in a microsecond",
     RECORD + ["-o", "r.csv", "--png", "o.png"], 65,
     "t.csv: line 4, column 1 (t_s): the 1e-06 s since the previous sample plan 4000 "
     "simulation steps, over the limit of 1000000 steps per second of gesture (the handle "
     "moves 1000 mm)",
     all_of(brush(), trajectory(rows=[[0, *HIGH, *REST], [1e-6, 1015, 40, 25, *REST]])))

# -- NUL bytes and control characters are shown, never cut the line -----------
case("nul-raw-in-brush", "a raw NUL byte inside a brush's JSON string", ["validate", "b.json"],
     65, "b.json: line 1, column 13: malformed JSON (syntax error while parsing value - invalid "
     "string: control character U+0000 (NUL) must be escaped to \\u0000; last read: "
     "'\"ro<U+0000>')", brush(text='{"name": "ro\0und"}'))
case("nul-raw-in-manifest", "a raw NUL byte inside a manifest's literal", BATCH_DRY, 65,
     "m.json: line 1, column 8: malformed JSON (syntax error while parsing value - invalid "
     "literal; last read: '\"a\": t<U+0000>')",
     all_of(STROKE, folder("out"), manifest(text='{"a": t\0rue}')))
case("nul-escaped-in-brush-key", "a brush key holding an escaped NUL", ["validate", "b.json"],
     65, "b.json: /na\\u0000me: unknown key 'na\\u0000me'",
     brush(edit=lambda b: b.update({"na\0me": 1})))
case("nul-in-session-header", "a NUL byte in a session's column header", ["replay", "r.csv",
     "--brush", "b.json", "-o", "o.png"], 65,
     "r.csv: line 2, column 1 (t\\u0000s): unknown column 't\\u0000s'",
     all_of(brush(), trajectory("r.csv", text="# bristle-trajectory/1\nt\0s,x_mm,y_mm,z_mm,"
                                "qw,qx,qy,qz\n0,15,40,25,1,0,0,0\n")))
case("nul-in-png-name", "an image whose name holds a newline", ["compare", "a\nb.png", "b.png"],
     66, "a\\u000ab.png: cannot read: No such file or directory",
     all_of(PNG, truncated(GOLD, "b.png", 10 ** 9)))

# -- JSON values: counted while parsing, before the document is built ----------
def many_values(name, n, key="description"):
    def step(d):
        fmt = "bristle-batch/1" if key == "jobs" else "bristle-brush/1"
        write(d, name, '{"format": "' + fmt + '", "' + key + '": [' + "0," * (n - 1) + "0]}")
    return step


case("json-values-over-limit", "a brush whose description lists 1,000,000 numbers (1,000,002 "
     "values in all)", ["validate", "b.json"], 65,
     "b.json: JSON: holds more than 1000000 values (numbers, strings, arrays, objects ...), "
     "over the limit", many_values("b.json", 1000000))
case("json-values-at-limit", "a manifest of exactly 1,000,000 values: parsed, and refused for "
     "what it is", BATCH_DRY, 65, "m.json: /jobs/0: must be a JSON object",
     all_of(folder("out"), many_values("m.json", 999997, "jobs")))
case("json-values-manifest", "a batch manifest of 2,000,000 numbers", BATCH_DRY, 65,
     "m.json: JSON: holds more than 1000000 values (numbers, strings, arrays, objects ...), "
     "over the limit", all_of(folder("out"), many_values("m.json", 2000000, "jobs")))

# -- PNG chunks longer than the file: refused before libpng allocates them -----
def text_chunk_bomb(name):
    """A 1x1 PNG whose tEXt chunk claims 1.7 GB (found by fuzz/png.cpp)."""
    def step(d):
        (d / name).write_bytes((SRC / "fuzz/regressions/png/text-chunk-claims-1.7GB").read_bytes())
    return step


case("png-text-chunk-bomb", "a 106-byte PNG whose tEXt chunk claims 1.7 GB",
     ["compare", "a.png", "a.png"], 65,
     "a.png: tEXt: a chunk of 1778384896 bytes is longer than the 65 bytes left in the file "
     "(corrupt or truncated PNG)", text_chunk_bomb("a.png"))

# -- brushes by name, and "-" for standard input and output ------------------
NO_NAME = ("; `bristle brushes` lists the library, and a path must contain '/' or end in "
           ".json")
case("brush-name-unknown", "a brush name found in no library folder",
     render("nope"), 66, "--brush nope: no brush named 'nope' in the library (looked for "
     "nope.json in {src}/scenes/brushes, {prefix}/share/bristle/brushes, lib)" + NO_NAME,
     all_of(STROKE, folder("lib")), env={"BRISTLE_BRUSH_PATH": "lib:"})
case("brush-name-unknown-validate", "`validate` of a brush name found nowhere, "
     "BRISTLE_BRUSH_PATH unset", ["validate", "nope"], 66,
     "nope: no brush named 'nope' in the library (looked for nope.json in "
     "{src}/scenes/brushes, {prefix}/share/bristle/brushes; BRISTLE_BRUSH_PATH is not set)"
     + NO_NAME, env={"BRISTLE_BRUSH_PATH": None})
case("brush-name-unknown-scene", "a scene stroke whose brush is a name found nowhere",
     ["validate", "s.json"], 66, "s.json: /strokes/0/brush: no brush named 'nope' in the "
     "library (looked for nope.json in {src}/scenes/brushes, {prefix}/share/bristle/brushes; "
     "BRISTLE_BRUSH_PATH is not set)" + NO_NAME,
     all_of(STROKE, scene(edit=lambda s: s["strokes"][0].update({"brush": "nope"}))),
     env={"BRISTLE_BRUSH_PATH": None})
case("brush-name-unknown-manifest", "a batch job whose brush is a name found nowhere",
     BATCH_DRY, 66, "m.json: /jobs/0/brush: no brush named 'nope' in the library (looked for "
     "nope.json in {src}/scenes/brushes, {prefix}/share/bristle/brushes, lib)" + NO_NAME,
     all_of(STROKE, folder("out"), folder("lib"),
            manifest(edit=lambda m: m["jobs"][0].update({"brush": "nope"}))),
     env={"BRISTLE_BRUSH_PATH": "lib"})
case("brush-name-fifo", "a brush name that is a FIFO in a BRISTLE_BRUSH_PATH folder",
     ["validate", "zz"], 66, "lib/zz.json: cannot read: is a FIFO" + NOT_REG,
     all_of(folder("lib"), fifo("lib/zz.json")), env={"BRISTLE_BRUSH_PATH": "lib"})
case("stdin-brush", "`--brush -`: only a trajectory is read from standard input",
     render("-", "t.csv", "-"), 64,
     "--brush -: only --trajectory can read standard input (-); give --brush a file", STROKE)
case("stdin-trajectory-empty", "`--trajectory -` with nothing on standard input",
     render("b.json", "-", "-"), 65,
     "stdin: line 1: empty file (expected '# bristle-trajectory/1')", brush())
case("stdout-twice", "`-o -` and `--trace -`: one standard output",
     render("b.json", "t.csv", "-", "--trace", "-"), 64,
     "--trace -: only -o can be standard output (-); give --trace a file", STROKE)
case("stats-stdout", "`render --stats -`: the stats are a file",
     render("b.json", "t.csv", "o.png", "--stats", "-"), 64,
     "--stats -: only -o can be standard output (-); give --stats a file", STROKE)
case("stats-is-trajectory", "`render --stats` onto the trajectory",
     render("b.json", "t.csv", "o.png", "--stats", "t.csv"), 64,
     "t.csv: --stats: is the same file as the input t.csv (--trajectory)" + OVER, STROKE)
case("record-session-stdout", "`record -o -`: the session is a file",
     RECORD + ["-o", "-"], 64,
     "-o -: only --png can be standard output (-); give -o a file", STROKE)
case("replay-no-brush-recorded", "`replay` without `--brush` of a session whose header names "
     "no brush", ["replay", "r.csv", "-o", "o.png"], 64,
     "r.csv: the header records no brush (no '# brush:' line); give --brush",
     all_of(brush(), session(rows=[[0, *HIGH, *REST], [1, *HIGH, *REST]])))


def session_of(brush_line, hash_of="b.json"):
    """A setup step: a session whose header records `brush_line` and the hash
    of the file hash_of (written first)."""
    def step(d):
        write(d, "r.csv", "# bristle-trajectory/1\n# bristle record: a live session\n"
              f"# brush: {brush_line}\n"
              f"# brush_fnv1a64: {fnv1a64((d / hash_of).read_bytes())}\n" + HEADER + "\n"
              + "".join(",".join(str(v) for v in [t, *HIGH, *REST]) + "\n" for t in (0, 1)))
    return step


case("replay-recorded-brush-changed", "`replay` without `--brush`: the recorded brush file "
     "changed since the recording", ["replay", "r.csv", "-o", "o.png"], 65,
     f"r.csv: brush_fnv1a64 {fnv1a64(b'{}')}: the brush b.json (from the header) is "
     f"{fnv1a64(b'[]')}: it changed since the recording; give --brush to replay with it anyway",
     all_of(brush(text="[]"), brush("old.json", text="{}"), session_of("b.json", "old.json")))
case("replay-recorded-brush-gone", "`replay` without `--brush`: the recorded brush file is gone",
     ["replay", "r.csv", "-o", "o.png"], 66, "gone.json: cannot read: No such file or directory",
     all_of(brush(), session_of("gone.json")))


def session_options(*lines):
    """A setup step: a session of b.json whose header records the render
    options `lines` ("--px-per-mm: 500"), as record writes them."""
    def step(d):
        write(d, "r.csv", "# bristle-trajectory/1\n# bristle record: a live session\n"
              "# brush: b.json\n"
              f"# brush_fnv1a64: {fnv1a64((d / 'b.json').read_bytes())}\n"
              + "".join(f"# {line}\n" for line in lines) + HEADER + "\n"
              + "".join(",".join(str(v) for v in [t, *HIGH, *REST]) + "\n" for t in (0, 1)))
    return step


case("replay-header-option-range", "`replay` of a session whose header records `--px-per-mm` "
     "500", ["replay", "r.csv", "-o", "o.png"], 65,
     "r.csv: header: --px-per-mm: Value 500 not in range 0.500000 to 100.000000",
     all_of(brush(), session_options("--paint: ultramarine", "--px-per-mm: 500")))
case("replay-header-unknown-option", "`replay` of a session whose header records an option "
     "the render does not have", ["replay", "r.csv", "-o", "o.png"], 65,
     "r.csv: header: --pain: not an option of the render (known: --paint, --load, --amount, "
     "--tip-length, --mix, --paper-tooth, --paper-scale, --paper-seed, --background, --impasto, "
     "--bits, --px-per-mm, --solver, --solver-max-iterations, --ipopt-option)",
     all_of(brush(), session_options("--pain: ultramarine")))
case("record-ipopt-option-newline", "`record --ipopt-option` holding a line break, which the "
     "session's header cannot hold: no allowed value holds one",
     RECORD + ["-o", "r.csv", "--ipopt-option", "tol=1\nx"], 64,
     "--ipopt-option tol=1\\u000ax: tol must be a finite number in [1e-12, 0.1]", STROKE)


# -- validate tells a JSON file's kind by its "format", and checks a manifest's jobs --
case("validate-no-format", "`validate` of JSON with no `format`: its kind is unknown",
     ["validate", "b.json"], 65, "b.json: /format: required key is missing: it names the "
     "file's kind (" + KNOWN_FORMATS + ")", brush(edit=lambda b: b.pop("format")))
case("validate-unknown-format", "`validate` of JSON whose `format` is no bristle format",
     ["validate", "b.json"], 65, "b.json: /format = \"bristle-paint/1\": unknown format ("
     + KNOWN_FORMATS + ")", brush(edit=lambda b: b.update(format="bristle-paint/1")))
case("validate-manifest-missing-brush", "`validate` of a batch manifest whose job names a "
     "missing brush", ["validate", "m.json"], 66,
     "m.json: /jobs/0/brush: b.json: cannot read: No such file or directory",
     all_of(trajectory(), manifest()))
case("validate-manifest-option-refused", "`validate` of a batch manifest whose stroke job sets "
     "an option `render --brush` does not take", ["validate", "m.json"], 65,
     "m.json: /jobs/0/options/at: bristle render refuses it: The following argument was not "
     "expected: --at", all_of(STROKE, manifest(edit=lambda m: m["jobs"][0].update(
         options={"at": 1.2}))))

# -- validate checks a brush with a trajectory as render does, by the same function --
LOW_START = all_of(brush(), trajectory(rows=[[0, 15, 40, -5, 1, 0, 0, 0],
                                             [1, 30, 40, 25, 1, 0, 0, 0]]))
PAIR_LOW = ("t.csv: line 3: the ferrule goes below the canvas (spine 0 root at z = -5 mm); "
            "z must stay >= 0")
case("render-starts-below", "`render` of a trajectory starting with the ferrule in the paper",
     render(), 65, PAIR_LOW, LOW_START)
case("validate-pair-starts-below", "`validate BRUSH TRAJ`: the same pair, the same message",
     ["validate", "b.json", "t.csv"], 65, PAIR_LOW, LOW_START)

# -- SVG path data: segments counted as they are read, refused before they are held --
def svg(name, body):
    """A setup step: an SVG of `body` in a 100 x 60 viewBox."""
    return lambda d: write(d, name, '<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 '
                           '60">\n' + body + '\n</svg>\n')


SEGMENTS = ("the SVG's paths hold more than 1000000 segments, the limit for an SVG (its paths "
            "are held in memory whole)")
case("svg-path-segments-over-limit", "an SVG `<path>` of a move and 1,000,000 tiny lines "
     "(1,000,001 segments)", ["import", "l.svg", "-o", "o.csv"], 65,
     'l.svg: <path id="long"> (line 2): d: ' + SEGMENTS,
     svg("l.svg", '<path id="long" d="M0 0' + " h.1" * 1000000 + '"/>'))
case("svg-path-segments-render", "the same SVG given to `render --trajectory`",
     ["render", "--brush", "round", "--trajectory", "l.svg", "-o", "o.png"], 65,
     'l.svg: <path id="long"> (line 2): d: ' + SEGMENTS,
     svg("l.svg", '<path id="long" d="M0 0' + " h.1" * 1000000 + '"/>'))
case("svg-polyline-segments-over-limit", "an SVG `<polyline>` of 1,000,001 points",
     ["import", "l.svg", "-o", "o.csv"], 65, "l.svg: <polyline> (line 2): points: " + SEGMENTS,
     svg("l.svg", '<polyline points="' + "0,0 " * 1000001 + '"/>'))
case("svg-segments-over-limit-across-paths", "an SVG of 1,001 `<path>`s of 1,000 segments each",
     ["import", "l.svg", "-o", "o.csv"], 65,
     'l.svg: <path id="p1001"> (line 1002): d: ' + SEGMENTS,
     svg("l.svg", "\n".join('<path id="p%d" d="M0 0%s"/>' % (k, " h.1" * 999)
                            for k in range(1, 1002))))

# -- legal in form, but surely a mistake: refused naming what was meant --------
case("png-output-jpg", "`render -o o.jpg`: bristle writes PNG only",
     render("b.json", "t.csv", "o.jpg"), 64,
     "render: -o o.jpg: bristle writes PNG only; use a .png name (or - for standard output)",
     STROKE)
case("diff-output-tiff", "`compare --diff d.tiff`: the difference image is a PNG too",
     ["compare", "a.png", "a.png", "--diff", "d.tiff"], 64,
     "compare: --diff d.tiff: bristle writes PNG only; use a .png name", PNG)
case("traj-semicolons", "a trajectory whose columns are separated by ';' (a spreadsheet export)",
     ["validate", "t.csv"], 65,
     "t.csv: line 2: columns are separated by ';'; bristle trajectories use ','",
     trajectory(text="# bristle-trajectory/1\n" + HEADER.replace(",", ";") + "\n"
                "0;15;40;25;1;0;0;0\n1;30;40;25;1;0;0;0\n"))
case("traj-tabs-render", "`render` of a trajectory in tab-separated columns", render(), 65,
     "t.csv: line 2: columns are separated by tabs; bristle trajectories use ','",
     all_of(brush(), trajectory(text="# bristle-trajectory/1\n" + HEADER.replace(",", "\t") +
                                "\n0\t15\t40\t25\t1\t0\t0\t0\n1\t30\t40\t25\t1\t0\t0\t0\n")))
case("brush-misspelt-required-key", "a brush whose required `spines` is spelt `spine`",
     ["validate", "b.json"], 65, "b.json: /spine: unknown key 'spine'; did you mean /spines?",
     brush(edit=lambda b: b.update({"spine": b.pop("spines")})))

# -- validate plans a pair's steps, and a scene's, as render does ---------------
case("validate-pair-span-1e7", "`validate BRUSH TRAJ` of two samples 1e7 s apart",
     ["validate", "b.json", "t.csv"], 65,
     "t.csv: line 4, column 1 (t_s): the trajectory plans 1200000001 "
     "simulation steps up to here, over the limit of 10000000 per trajectory", LONG)
case("validate-scene-span-1e7", "`validate` of a scene stroke whose trajectory spans 1e7 s",
     ["validate", "s.json"], 65,
     "t.csv: line 4, column 1 (t_s): the trajectory plans 1200000001 simulation steps up to "
     "here, over the limit of 10000000 per trajectory",
     all_of(LONG, scene(edit=lambda s: s.update(sim={"rate_hz": 120}))))

# -- all outputs or none: a run that fails on one output leaves none ---------
def old(name, text="old\n"):
    """A setup step: an earlier output, which a failed run must leave as it was."""
    return lambda d: write(d, name, text)


# The press of the S-curve, its first half second: a stroke whose trace (about
# 0.6 MB) outgrows a 256 KB file limit while its PNG (a few KB) does not.
PRESS = all_of(brush(), trajectory(text="".join(S_CURVE.read_text().splitlines(True)[:55])))
case("render-trace-disk-full", "`render -o o.png --trace o.jsonl` over an earlier `o.png`, with "
     "every file limited to 256 KB (as a full disk): the 0.6 MB trace fails after the PNG was "
     "written; the earlier PNG stays, no new file", ["render", "-q", "--brush", "b.json",
     "--trajectory", "t.csv", "-o", "o.png", "--trace", "o.jsonl", "--stats", "s.json",
     "--solver", "ipopt"], 74,
     "o.jsonl: write failed: File too large", all_of(PRESS, old("o.png")), fsize=1 << 18)
case("scene-trace-disk-full", "the same for a scene: `render s.json -o o.png --trace o.jsonl "
     "--stats s.json` over an earlier `o.png` and `st.json`, files limited to 256 KB",
     ["render", "-q", "s.json", "-o", "o.png", "--trace", "o.jsonl", "--stats", "st.json"], 74,
     "o.jsonl: write failed: File too large",
     all_of(PRESS, scene(edit=lambda s: s.update(solver="ipopt")), old("o.png"), old("st.json")),
     fsize=1 << 18)
TWO_PATHS = svg("l.svg", '<path d="M10 10 h5"/>\n'
                '<path d="M10 30 c20 -20 40 20 60 0 s40 20 20 20 s-40 -20 -60 0"/>')
case("import-second-stroke-fails", "`import` to a scene of two paths, every file limited to "
     "4 KB: the second stroke's 10 KB trajectory fails; the first stroke's earlier file stays, "
     "no scene", ["import", "l.svg", "-o", "s.json"], 74,
     "s-stroke-002.csv: write failed: File too large",
     all_of(TWO_PATHS, old("s-stroke-001.csv")), fsize=4096)
LINKED = ": cannot create output: is a symbolic link; bristle never writes through a link nor " \
         "replaces it (name the file itself)"
case("out-symlink-to-file", "`-o` is a symbolic link to a file that is no input",
     render(out="l.png"), 73, "l.png" + LINKED,
     all_of(STROKE, old("victim.png"), symlink("l.png", "victim.png")))
case("out-symlink-dangling", "`-o` is a dangling symbolic link: nothing is made where it points",
     render(out="l.png"), 73, "l.png" + LINKED, all_of(STROKE, symlink("l.png", "made.png")))
case("trace-symlink-to-file", "`--trace` is a symbolic link to a file outside the folder",
     render("b.json", "t.csv", "o.png", "--trace", "l.jsonl"), 73, "l.jsonl" + LINKED,
     all_of(STROKE, symlink("l.jsonl", "/etc/hostname")))


# -- Ipopt options: only those that change the solve, each value checked before Ipopt --
NOT_ALLOWED = " is not an Ipopt option bristle allows (bristle help ipopt-option lists them)"


def ipopt(value, out="o.png"):
    return render("b.json", "t.csv", out, "--ipopt-option", value)


case("ipopt-option-output-file-input", "`--ipopt-option output_file=t.csv`: Ipopt would truncate "
     "the trajectory", ipopt("output_file=t.csv"), 64,
     "--ipopt-option output_file=t.csv: output_file" + NOT_ALLOWED, STROKE)
case("ipopt-option-output-file-elsewhere", "`--ipopt-option output_file=` a file outside the "
     "outputs", ipopt("output_file=/tmp/bristle-ipopt-leak.txt"), 64,
     "--ipopt-option output_file=/tmp/bristle-ipopt-leak.txt: output_file" + NOT_ALLOWED, STROKE)
case("ipopt-option-print-level-stdout", "`-o - --ipopt-option print_level=5`: Ipopt's log would "
     "go into the PNG stream", ipopt("print_level=5", "-"), 64,
     "--ipopt-option print_level=5: print_level" + NOT_ALLOWED, STROKE)
case("ipopt-option-option-file", "`--ipopt-option option_file_name=/etc/passwd`",
     ipopt("option_file_name=/etc/passwd"), 64,
     "--ipopt-option option_file_name=/etc/passwd: option_file_name" + NOT_ALLOWED, STROKE)
case("ipopt-option-misspelt", "`--ipopt-option mu_strategie=adaptive`",
     ipopt("mu_strategie=adaptive"), 64,
     "--ipopt-option mu_strategie=adaptive: mu_strategie" + NOT_ALLOWED +
     "; did you mean mu_strategy?", STROKE)
case("ipopt-option-tol-nan", "`--ipopt-option tol=nan`, which hung", ipopt("tol=nan"), 64,
     "--ipopt-option tol=nan: tol must be a finite number in [1e-12, 0.1]", STROKE)
case("ipopt-option-bound-push-inf", "`--ipopt-option bound_push=inf`, which hung",
     ipopt("bound_push=inf"), 64,
     "--ipopt-option bound_push=inf: bound_push must be a finite number in [1e-12, 1]", STROKE)
case("ipopt-option-cpu-time-nan", "`--ipopt-option max_cpu_time=nan`",
     ipopt("max_cpu_time=nan"), 64,
     "--ipopt-option max_cpu_time=nan: max_cpu_time must be a finite number in [0.001, 1e+06]",
     STROKE)
case("ipopt-option-max-iter-wraps", "`--ipopt-option max_iter=4294967496`, which wrapped to 200",
     ipopt("max_iter=4294967496"), 64,
     "--ipopt-option max_iter=4294967496: max_iter must be an integer in [1, 100000]", STROKE)
case("ipopt-option-choice", "`--ipopt-option linear_solver=ma57`, a solver this build lacks",
     ipopt("linear_solver=ma57"), 64,
     "--ipopt-option linear_solver=ma57: linear_solver must be one of dense, mumps", STROKE)
case("ipopt-option-batch-job", "a batch job's `ipopt-option` naming `output_file`", BATCH_RUN, 65,
     "m.json: /jobs/0/options/ipopt-option/1: output_file=x.txt: output_file" + NOT_ALLOWED,
     all_of(STROKE, job_options({"ipopt-option": ["tol=1e-8", "output_file=x.txt"]})))
case("ipopt-option-replay-header", "`replay` of a session whose header records "
     "`--ipopt-option: print_level=5`", ["replay", "r.csv", "-o", "-"], 65,
     "r.csv: header: --ipopt-option print_level=5: print_level" + NOT_ALLOWED,
     all_of(brush(), session_options("--ipopt-option: print_level=5")))

# -- JSON: a key twice in one object is refused, by every reader -----------------
DUPLICATE = ": the object already holds it (one of the two would be lost)"
case("json-duplicate-brush", "a brush whose `format` is given twice", ["validate", "b.json"], 65,
     'b.json: /format: duplicate key "format"' + DUPLICATE,
     brush(text='{"format": "bristle-brush/1", "format": "bristle-brush/1", "name": "x"}'))
case("json-duplicate-scene", "a scene whose canvas gives `size_mm` twice",
     ["render", "s.json", "-o", "o.png"], 65,
     's.json: /canvas/size_mm: duplicate key "size_mm"' + DUPLICATE,
     all_of(STROKE, scene(text='{"format": "bristle-scene/1", "canvas": {"size_mm": [9, 9], '
                        '"size_mm": [1, 1]}, "strokes": []}')))
case("json-duplicate-sheet", "a sheet listing `brushes` twice", ["sheet", "sh.json", "-o", "o.png"],
     65, 'sh.json: /brushes: duplicate key "brushes"' + DUPLICATE,
     all_of(STROKE, sheet(text='{"format": "bristle-sheet/1", "brushes": ["b.json"], '
                         '"trajectories": ["t.csv"], "brushes": ["round"]}')))
case("json-duplicate-batch-output", "a batch job whose `output` is given twice, the second "
     "outside `--out`", BATCH_RUN, 65,
     'm.json: /jobs/1/output: duplicate key "output"' + DUPLICATE,
     all_of(STROKE, manifest(text='{"format": "bristle-batch/1", "jobs": [{"id": "a", "brush": '
                            '"b.json", "trajectory": "t.csv"}, {"output": "b.png", "brush": '
                            '"b.json", "trajectory": "t.csv", "output": "../b.png"}]}')))
case("json-duplicate-in-array", "a duplicate key in an object inside arrays (the pointer counts "
     "the elements)", ["validate", "s.json"], 65,
     's.json: /strokes/1/paint/paints: duplicate key "paints"' + DUPLICATE,
     all_of(STROKE, scene(text='{"format": "bristle-scene/1", "strokes": [{"brush": "b.json"}, '
                        '{"paint": {"paints": ["sumi-ink"], "paints": []}}]}')))

# -- messages: one escaping rule (C0, DEL, C1 controls, bytes that are not UTF-8) --
case("batch-id-c1-control", "a job id holding a C1 control (CSI, U+009B)", BATCH_DRY, 65,
     'm.json: /jobs/0/id = "one\\u009b2J": must hold no control character',
     all_of(STROKE, folder("out"), manifest(edit=job_edit(id="one\x9b2J"))))
case("c1-in-json-key", "a brush key holding a C1 control", ["validate", "b.json"], 65,
     "b.json: /na\\u009bme: unknown key 'na\\u009bme'",
     brush(edit=lambda b: b.update({"na\x9bme": 1})))
case("invalid-utf8-in-csv-header", "a trajectory column name with a byte that is not UTF-8",
     ["validate", "t.csv"], 65,
     "t.csv: line 2, column 2 (x_\\xffmm): unknown column 'x_\\xffmm'",
     lambda d: (d / "t.csv").write_bytes(b"# bristle-trajectory/1\nt_s,x_\xffmm,y_mm,z_mm,qw,qx,"
                                         b"qy,qz\n"))
case("c1-in-csv-header", "a trajectory column name holding a C1 control in UTF-8",
     ["validate", "t.csv"], 65,
     "t.csv: line 2, column 2 (x_\\u0085mm): unknown column 'x_\\u0085mm'",
     lambda d: (d / "t.csv").write_bytes(b"# bristle-trajectory/1\nt_s,x_\xc2\x85mm,y_mm,z_mm,"
                                         b"qw,qx,qy,qz\n"))

# -- messages that name the right file, field or option -----------------------------
case("scene-canvas-subpixel", "a scene canvas of 1e-300 mm", ["render", "s.json", "-o", "o.png"],
     65, "s.json: /canvas/size_mm: 1e-300 x 1e-300 mm at 4 px/mm is less than one pixel a side; "
     "each side must be at least 1 px",
     all_of(STROKE, scene(edit=lambda s: s["canvas"].update(size_mm=[1e-300, 1e-300]))))
case("import-pressure-nan", "`import --pressure 0:nan`: the option's, not the SVG's",
     ["import", "l.svg", "-o", "o.csv", "--pressure", "0:nan"], 64,
     "--pressure: 0:nan: '0:nan' does not parse (a pressure profile is 'u:p u:p ...', u the "
     "fraction of the stroke's length in [0, 1] increasing, p a pressure in [0, 1]; or one "
     "pressure)", svg("l.svg", '<path d="M0 0 h50"/>'))

case("output-empty-name", "`render -o ''`: an empty name", render(out=""), 64,
     "--output: an empty name: give a file name (or - where standard output is allowed) "
     "(see bristle --help)", STROKE)
case("trace-empty-name", "`render --trace ''`, which was taken for no trace",
     render("b.json", "t.csv", "o.png", "--trace", ""), 64,
     "--trace: an empty name: give a file name (or - where standard output is allowed) "
     "(see bristle --help)", STROKE)
case("sheet-title-too-wide", "a sheet whose title of 3,000 letters is wider than a picture may be",
     ["sheet", "sh.json", "-o", "o.png"], 65,
     "sh.json: /title: the title alone makes the sheet 63028 px wide, above the limit of "
     "16384 px a side; shorten it",
     all_of(STROKE, sheet(edit=lambda s: s.update(title="W" * 3000))))

# -- small things: numbers read whole, the environment checked ------------------------
SEED_RULE = "must be a whole number in [0, 18446744073709551615] (see bristle --help)"
case("paper-seed-negative", "`--paper-seed -1`, which CLI11 read as 2^64 - 1",
     render("b.json", "t.csv", "o.png", "--paper-seed", "-1"), 64,
     "--paper-seed: '-1' " + SEED_RULE, STROKE)
case("paper-seed-too-large", "`--paper-seed` past 2^64",
     render("b.json", "t.csv", "o.png", "--paper-seed", "99999999999999999999999"), 64,
     "--paper-seed: '99999999999999999999999' " + SEED_RULE, STROKE)
case("slurm-step-zero", "a Slurm array task with `SLURM_ARRAY_TASK_STEP=0`", BATCH_DRY, 64,
     "SLURM_ARRAY_TASK_STEP=0: must be at least 1 (the array's step between task ids)",
     all_of(STROKE, folder("out"), manifest()),
     env={"SLURM_ARRAY_TASK_ID": "1", "SLURM_ARRAY_TASK_COUNT": "4",
          "SLURM_ARRAY_TASK_STEP": "0"})
case("gallium-driver-unknown", "`GALLIUM_DRIVER=bogus`, a driver OSMesa does not have",
     render(), 64, "GALLIUM_DRIVER=bogus: OSMesa supports only llvmpipe or softpipe; unset it "
     "to use llvmpipe", STROKE, env={"GALLIUM_DRIVER": "bogus"})

# -- fit: the measurement table and the free parameters, checked before any stroke -----
def table(text, name="m.csv"):
    return lambda d: write(d, name, text)


FIT = ["fit", "b.json", "m.csv", "-o", "f.json", "--no-cache"]
GOOD_TABLE = "depth_mm,width_mm,drag_mm,offset_mm\n1,1.8,1.5,0\n2,2.2,2,1\n4,3.5,4.5,2.5\n"
case("fit-table-misnamed-column", "a measurement table whose header misspells `width_mm`", FIT,
     65, "m.csv: line 2, column 2 (widht_mm): unknown column 'widht_mm'; did you mean width_mm?",
     all_of(brush(), table("# a real brush\ndepth_mm,widht_mm,drag_mm\n1,2,3\n")))
case("fit-table-missing-column", "a measurement table without `drag_mm`", FIT, 65,
     "m.csv: line 1: missing column drag_mm (the header must name depth_mm, width_mm, drag_mm)",
     all_of(brush(), table("depth_mm,width_mm\n1,2\n2,3\n4,5\n")))
case("fit-table-not-a-number", "a measured width of `wide`", FIT, 65,
     "m.csv: line 3, column 2 (width_mm): 'wide' is not a number",
     all_of(brush(), table("depth_mm,width_mm,drag_mm\n1,2,3\n2,wide,3\n")))
case("fit-table-negative", "a negative drag", FIT, 65,
     "m.csv: line 2, column 3 (drag_mm): -1.5 must be >= 0 (a length in mm)",
     all_of(brush(), table("depth_mm,width_mm,drag_mm\n1,2,-1.5\n")))
case("fit-table-too-few-rows", "two rows past depth 0 for the round's three free parameters",
     FIT, 65, "m.csv: line 4: 2 rows with a depth above 0, fewer than the 3 free parameters "
     "(stiffness_scale, stiffness_taper, tip_spread): a fit needs a row per parameter at least",
     all_of(brush(), table("depth_mm,width_mm,drag_mm\n0,0,0\n1,2,2\n2,3,3\n")))
case("fit-table-too-deep", "a 40 mm press for a brush of 20 mm of hair", FIT, 65,
     "m.csv: line 5, column 1 (depth_mm): 40 mm is deeper than 'round' can press: its ferrule "
     "reaches the paper 20 mm past first contact",
     all_of(brush(), table(GOOD_TABLE + "40,20,9,3\n")))
case("fit-params-misspelt", "a `--params` file naming `stifness_scale`",
     FIT + ["--params", "p.json"], 65,
     "p.json: /stifness_scale: unknown key 'stifness_scale'; did you mean /stiffness_scale?",
     all_of(brush(), table(GOOD_TABLE), lambda d: write(d, "p.json",
                                                         '{"stifness_scale": [0.5, 2]}')))
case("fit-params-out-of-range", "a `--params` tip spread past 1", FIT + ["--params", "p.json"],
     65, "p.json: /tip_spread = [0.5,1.5]: must lie within [0, 1]",
     all_of(brush(), table(GOOD_TABLE), lambda d: write(d, "p.json", '{"tip_spread": [0.5, 1.5]}')))
case("fit-plot-without-gnuplot", "`fit --plot` with no gnuplot on PATH", FIT + ["--plot", "f.png"],
     69, "--plot: gnuplot not found on PATH (Debian: apt install gnuplot-nox; scripts/install-deps "
     "installs it)", all_of(brush(), table(GOOD_TABLE)), env={"PATH": "/nonexistent"})
case("measure-compare-bad-table", "`measure --compare` a table with a non-numeric depth",
     ["measure", "b.json", "--plot", "p.png", "--compare", "m.csv"], 65,
     "m.csv: line 2, column 1 (depth_mm): 'one' is not a number",
     all_of(brush(), table("depth_mm,width_mm\none,2\n")))
case("traj-quoted-comma", "a trajectory cell in quotes holding a ',' (a decimal comma)",
     ["validate", "t.csv"], 65, "t.csv: line 3, column 2 (x_mm): '1,5' is not a number",
     trajectory(text="# bristle-trajectory/1\n" + HEADER + "\n0,\"1,5\",40,25,1,0,0,0\n"))

case("brush-flag-too-long", "a brush whose flagged hair ends are 8 mm long",
     ["validate", "b.json"], 65,
     "b.json: /paint/flag_mm = 8: must be in [0, 5] (mm of split hair ends)",
     brush(edit=lambda b: b.update(paint={"capacity": 1.0, "flag_mm": 8})))
case("brush-wicking-negative", "a brush whose hair wicks a negative share of its paint",
     ["validate", "b.json"], 65,
     "b.json: /paint/wicking = -0.5: must be in [0, 1] (share of the reservoir flow)",
     brush(edit=lambda b: b.update(paint={"capacity": 1.0, "wicking": -0.5})))
case("brush-flat-load-zero", "a spine whose bundle is pressed flat by no load at all",
     ["validate", "b.json"], 65,
     "b.json: /spines/0/flat_load_n = 0: must be in (0, 1] (N that press the bundle flat)",
     brush(edit=lambda b: b["spines"][0].update(flat_load_n=0)))

case("render-preset-unknown", "`render --preset` a name no preset has",
     ["render", "--brush", "b.json", "--trajectory", "t.csv", "--preset", "poster", "-o", "o.png"],
     64, "--preset: poster not in {default,thumbnail} (see bristle --help)",
     all_of(brush(), trajectory()))

case("brush-spread-negative", "a brush whose squashed hair spreads with a negative stiffness",
     ["validate", "b.json"], 65,
     "b.json: /volume/spread_n_per_mm = -1: must be in [0, 1000] N/mm (0: a squashed bundle "
     "does not spread)",
     brush(edit=lambda b: b.update(volume={"min_separation": 0.8, "spread_n_per_mm": -1})))

CASES_END = None  # the cases are appended above this line

if __name__ == "__main__":
    sys.exit(main())
