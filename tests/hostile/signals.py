#!/usr/bin/env python3
"""Long runs stopped by a signal (SIGINT, SIGTERM and every other catchable
signal whose default action ends the process), and their progress on a non-terminal
(docs/errors.md, "Long runs").

Each case starts a long valid render in a fresh folder (catalogue.py's inputs),
waits until its temporary output exists, sends the signal, and checks:
  - the exit status is the signal (the default action, after the cleanup);
  - no temporary file (NAME.tmp-PID) and no output is left, and the inputs are
    unchanged (catalogue.py's snapshot).
The progress case checks that with stderr a pipe a long render prints whole
"bristle: progress: ..." lines at the interval BRISTLE_PROGRESS_SECONDS sets,
with the plan's fixed step total and the time left.

  signals.py --list                 the case ids
  signals.py --bristle BIN ID...    runs cases
"""

import argparse
import os
import re
import resource
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import catalogue  # noqa: E402  (the inputs and the snapshot of a case's folder)

# A step of 0.01 mm: the S-curve takes minutes, so the signal comes mid-run.
SLOW = ["--max-step-mm", "0.01"]
STROKE = ["render", "--brush", "b.json", "--trajectory", "t.csv", "-o", "o.png"]
WAIT_S = 60


def scene_setup(d):
    catalogue.STROKE(d)
    catalogue.scene(edit=lambda s: s.update(sim={"max_step_mm": 0.01}))(d)


CASES = {
    "sigterm-render-trace-forces": (STROKE + ["--trace", "o.jsonl", "--forces", "f.csv"] + SLOW,
                                    signal.SIGTERM, catalogue.STROKE),
    "sigint-render-trace": (STROKE + ["--trace", "o.jsonl"] + SLOW, signal.SIGINT,
                            catalogue.STROKE),
    "sigterm-scene-trace": (["render", "s.json", "-o", "o.png", "--trace", "o.jsonl"],
                            signal.SIGTERM, scene_setup),
}
# Every other catchable signal whose default action ends the process cleans up
# alike (engine/base/temp_files.cpp); the faults of a bad instruction are left out.
OTHER_SIGNALS = ["SIGHUP", "SIGQUIT", "SIGABRT", "SIGUSR1", "SIGUSR2", "SIGPIPE", "SIGALRM",
                 "SIGSTKFLT", "SIGXCPU", "SIGXFSZ", "SIGVTALRM", "SIGPROF", "SIGIO", "SIGPWR",
                 "SIGRTMIN", "SIGRTMAX"]
for _name in OTHER_SIGNALS:
    CASES[_name.lower() + "-render-trace"] = (STROKE + ["--trace", "o.jsonl"] + SLOW,
                                              getattr(signal, _name), catalogue.STROKE)


def no_core_dump():
    """SIGQUIT and SIGABRT dump core by default; a core file is not an output."""
    resource.setrlimit(resource.RLIMIT_CORE, (0, 0))


def temp_files(d):
    return sorted(p.name for p in d.iterdir() if ".tmp-" in p.name)


def run_signal_case(bristle, cid):
    args, sig, setup = CASES[cid]
    problems = []
    with tempfile.TemporaryDirectory(prefix="bristle-signal-") as tmp:
        d = Path(tmp)
        setup(d)
        before = catalogue.snapshot(d)
        p = subprocess.Popen([bristle, *args], cwd=d, stdin=subprocess.DEVNULL,
                             stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                             preexec_fn=no_core_dump)
        deadline = time.monotonic() + WAIT_S
        while not temp_files(d) and p.poll() is None and time.monotonic() < deadline:
            time.sleep(0.02)
        if p.poll() is not None:
            return [f"ended ({p.returncode}) before its temporary file appeared: "
                    f"{p.stderr.read().decode(errors='replace')!r}"]
        seen = temp_files(d)
        if not seen:
            p.kill()
            p.wait()
            return [f"no temporary file after {WAIT_S} s"]
        time.sleep(0.3)  # well inside the run
        p.send_signal(sig)
        try:
            p.wait(timeout=WAIT_S)
        except subprocess.TimeoutExpired:
            p.kill()
            p.wait()
            return [f"still running {WAIT_S} s after {signal.Signals(sig).name}"]
        if p.returncode != -sig:
            problems.append(f"exit status {p.returncode}, expected {-sig} "
                            f"({signal.Signals(sig).name})")
        after = catalogue.snapshot(d)
        for name in sorted(set(before) | set(after)):
            if name not in after:
                problems.append(f"{name} was removed")
            elif name not in before:
                problems.append(f"{name} was left behind (temporary files were {seen})")
            elif before[name] != after[name]:
                problems.append(f"{name} was changed")
    return problems


PROGRESS = re.compile(r"bristle: progress: step (\d+)/(\d+) \( *\d+%\) after (\d+) s"
                      r"(, about \d+(\.\d)? (s|min|h) left)?")


def run_progress_case(bristle):
    """A render with stderr a pipe prints a whole progress line per interval."""
    with tempfile.TemporaryDirectory(prefix="bristle-progress-") as tmp:
        d = Path(tmp)
        catalogue.STROKE(d)
        env = dict(os.environ, BRISTLE_PROGRESS_SECONDS="1")
        p = subprocess.Popen([bristle, *STROKE, *SLOW], cwd=d, env=env,
                             stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                             stderr=subprocess.PIPE)
        lines = [p.stderr.readline().decode(errors="replace") for _ in range(2)]
        p.send_signal(signal.SIGINT)
        rest = p.stderr.read().decode(errors="replace")
        p.wait()
        problems = []
        matches = [PROGRESS.fullmatch(line.rstrip("\n")) for line in lines]
        for line, m in zip(lines, matches):
            if not m or not line.endswith("\n"):
                problems.append(f"not a progress line: {line!r}")
        if all(matches):
            # The plan's total stays put, and the time left is shown on every
            # line past the rule's 2 % and 1 s (cli/progress.h). A sanitizer
            # build may not get that far in 2 s; a release build always does.
            if matches[0].group(2) != matches[1].group(2):
                problems.append(f"the step total changed: {lines!r}")
            for line, m in zip(lines, matches):
                done = int(m.group(1)) / int(m.group(2))
                if done >= 0.02 and int(m.group(3)) >= 1 and not m.group(4):
                    problems.append(f"no time left past 2 %: {line!r}")
        if "\r" in rest or "\r" in "".join(lines):
            problems.append("a carriage return on a non-terminal")
        if p.returncode != -signal.SIGINT:
            problems.append(f"exit status {p.returncode}, expected {-signal.SIGINT}")
        if temp_files(d) or (d / "o.png").exists():
            problems.append(f"left behind: {temp_files(d)}")
        return problems


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--list", action="store_true")
    ap.add_argument("--bristle")
    ap.add_argument("ids", nargs="*")
    a = ap.parse_args()
    ids = list(CASES) + ["progress-on-a-pipe"]
    if a.list:
        print(";".join(ids))
        return 0
    failed = 0
    for cid in a.ids or ids:
        problems = (run_progress_case(a.bristle) if cid == "progress-on-a-pipe"
                    else run_signal_case(a.bristle, cid))
        print(f"{cid}: {'ok' if not problems else 'FAIL'}")
        for pr in problems:
            print("  " + pr)
        failed += bool(problems)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
