#!/usr/bin/env python3
"""Every bristle example the user is shown, run, so that none can rot.

The examples are extracted, not listed here:
  - README.md: each `build/cli/bristle ...` line of a ```sh block (with its
    `\\` continuation lines), and each inline `bristle CMD ARG...` code span;
  - the help: each `bristle ...` line under "Examples:" in `bristle --help`
    and in `bristle help CMD` for every command `bristle --help` lists.
Lines that run something other than bristle (scripts/..., sbatch) are not
bristle examples and are left to their own tests.

Each runs through the shell, in the order shown, in a scratch folder that holds the source tree's
scenes/, golden/, scripts/ and data/ (as links), build/cli/bristle (a link to the
binary under test) and the placeholder files the examples name (my-brushes/, T.csv, a
session.csv, jobs.json, the images compare is shown on). An example must exit
0, or with the code EXPECTED gives it (recording with no haptic device here is
exit 69, as documented). An example still running after TIME_LIMIT_S (a whole
library sheet, a batch), or SHIPPED_LIMIT_S for a shipped file, has passed
bristle's checks of its command line and inputs, which come before any long
run; it is stopped there and counted as started.

  run_examples.py --bristle BIN --list      the examples, one per line
  run_examples.py --bristle BIN             runs them all (exit 1 if any fails)
"""

import argparse
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

SRC = Path(__file__).resolve().parents[2]
# bristle reads and checks its command line and every input before it starts
# a long run (an example with a bad input fails in well under a second), so 5 s
# shows an example's command line and inputs are accepted. The quick examples,
# among them those whose outputs a later example reads (press.png, session.csv:
# 2-3 s on a loaded machine), finish inside it; the longer ones
# (a measure, a fit, a whole sheet or batch) are stopped there, and their full
# runs have tests of their own (test_cli_measure, test_cli_fit, run_shipped.py).
# A stopped example counts as started, not as failed.
TIME_LIMIT_S = 5
# An example that renders a whole shipped scene, sheet or manifest is rendered
# in full by its shipped.* test (run_shipped.py); here it need only show that
# its command line and inputs pass bristle's checks, which take well under a
# second, so it is stopped sooner.
SHIPPED = re.compile(r"scenes/(paintings|sheets|batch)/[^ /]+\.json")
SHIPPED_LIMIT_S = 1.5
# Examples that cannot succeed on a machine without the hardware they need:
# the regular expression of the command, and the exit code and stderr text
# they must give instead.
EXPECTED = [
    (r"^bristle record --brush round -o session\.csv --png live\.png$", 69,
     "--device none --trajectory T.csv"),
]


def readme_examples():
    text = (SRC / "README.md").read_text()
    out = []
    for block in re.findall(r"```sh\n(.*?)```", text, re.S):
        lines = block.split("\n")
        i = 0
        while i < len(lines):
            line = lines[i]
            cmd = line
            while cmd.rstrip().endswith("\\") and i + 1 < len(lines):
                i += 1
                cmd = cmd.rstrip()[:-1].rstrip() + " " + lines[i].strip()
            i += 1
            cmd = re.sub(r"\s+#.*$", "", cmd).strip()  # a trailing comment
            if cmd.startswith("build/cli/bristle "):
                out.append(("README.md", "bristle " + cmd[len("build/cli/bristle "):]))
    for span in re.findall(r"`(bristle [^`]+)`", text.replace("\n", " ")):
        span = re.sub(r"\s+", " ", span)
        if len(span.split()) >= 3:  # a command with an argument, not a name
            out.append(("README.md", span))
    return out


def help_examples(bristle):
    def examples(args):
        text = subprocess.run([bristle, *args], capture_output=True, text=True).stdout
        if "Examples:\n" not in text:
            return []
        lines, out, i = text.split("Examples:\n", 1)[1].split("\n"), [], 0
        while i < len(lines) and lines[i].startswith("  "):
            cmd = lines[i].strip()
            while cmd.endswith("\\") and i + 1 < len(lines):
                i += 1
                cmd = cmd[:-1].rstrip() + " " + lines[i].strip()
            i += 1
            if cmd.startswith("bristle "):
                out.append(("bristle " + " ".join(args), cmd))
        return out

    top = subprocess.run([bristle, "--help"], capture_output=True, text=True).stdout
    commands = re.findall(r"^  ([a-z]+) ", top.split("Subcommands:\n", 1)[1].split("\n\n")[0],
                          re.M)
    found = examples(["--help"])
    for c in commands:
        found += examples(["help", c])
    return found


def all_examples(bristle):
    seen, out = set(), []
    for where, cmd in readme_examples() + help_examples(bristle):
        if cmd not in seen:
            seen.add(cmd)
            out.append((where, cmd))
    return out


def scratch(bristle):
    d = Path(tempfile.mkdtemp(prefix="bristle-examples-"))
    for name in ("scenes", "golden", "scripts", "data"):
        (d / name).symlink_to(SRC / name)
    (d / "build/cli").mkdir(parents=True)
    (d / "build/cli/bristle").symlink_to(Path(bristle).resolve())
    env = dict(os.environ)
    env.pop("GALLIUM_DRIVER", None)
    env["XDG_CACHE_HOME"] = str(d / "cache")  # `fit` keeps its cache here, not in the user's
    (d / "my-brushes").mkdir()
    shutil.copy(SRC / "scenes/brushes/round.json", d / "my-brushes/house.json")
    lines = (SRC / "scenes/trajectories/straight-pull.csv").read_text().split("\n")
    (d / "T.csv").write_text("\n".join(lines[:60]) + "\n")

    def run(*args):
        subprocess.run([bristle, *args], cwd=d, env=env, check=True, capture_output=True)

    run("render", "-q", "--brush", "round", "--trajectory", "T.csv", "-o", "ref.png")
    run("record", "-q", "--device", "none", "--brush", "round", "--trajectory", "T.csv",
        "-o", "session.csv")
    for name in ("new.png", "a.png", "b.png"):
        shutil.copy(SRC / "golden/round-s-curve.png", d / name)
    # A manifest of one short stroke, its paths relative to the scratch folder.
    (d / "jobs.json").write_text('{"format": "bristle-batch/1", "jobs": [{"id": "dab", '
                                 '"brush": "scenes/brushes/round.json", "trajectory": "T.csv"}]}')
    return d, env


def run_one(d, env, bristle, cmd, limit_s):
    shell = "bristle() { \"$BRISTLE_BIN\" \"$@\"; }\n" + cmd
    p = subprocess.Popen(["bash", "-c", shell], cwd=d, env={**env, "BRISTLE_BIN": bristle},
                         stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                         stdin=subprocess.DEVNULL, start_new_session=True)
    try:
        _, err = p.communicate(timeout=limit_s)
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGTERM)
        p.communicate()
        return None, ""
    return p.returncode, err.decode(errors="replace")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bristle", required=True)
    ap.add_argument("--list", action="store_true")
    a = ap.parse_args()
    bristle = str(Path(a.bristle).resolve())
    examples = all_examples(bristle)
    if a.list:
        for where, cmd in examples:
            print(f"{where}: {cmd}")
        return 0
    if len(examples) < 20:
        print(f"only {len(examples)} examples found: the extraction is broken")
        return 1
    d, env = scratch(bristle)
    failed = 0
    try:
        # In order, one at a time: an example may use what one before it made
        # (README's pipe into compare, replay of the recorded session).
        for where, cmd in examples:
            t0 = time.monotonic()
            limit_s = SHIPPED_LIMIT_S if SHIPPED.search(cmd) else TIME_LIMIT_S
            code, err = run_one(d, env, bristle, cmd, limit_s)
            elapsed = time.monotonic() - t0
            want, text = 0, ""
            for pattern, c, t in EXPECTED:
                if re.search(pattern, cmd):
                    want, text = c, t
            if code is None:
                verdict = f"ok (still running after {limit_s} s: started)"
            elif code == want and text in err:
                verdict = "ok" if want == 0 else f"ok (exit {code}, as expected here)"
            else:
                verdict = f"FAIL: exit {code}, expected {want}: {err.strip()[-300:]}"
                failed += 1
            print(f"{where}: {cmd}\n  {verdict} ({elapsed:.1f} s)")
    finally:
        shutil.rmtree(d, ignore_errors=True)
    print(f"{len(examples)} examples, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
