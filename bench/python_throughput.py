#!/usr/bin/env python3
"""Throughput of the Python module on the data-set strokes (python/examples/
stroke_dataset.py: 10-30 mm curves pressed 1-5 mm, 0.3 s each, the round at
2 px/mm), run by hand, never by ctest (docs/python.md, "Speed"):

  - strokes/s through render_many at threads=1 and threads=2 (Ipopt, or --solver);
  - the module's own cost per stroke: the package's Python (option checks,
    arrays, the Stroke) against the call into the engine it wraps;
  - with --getrusage, the system calls Ipopt's timers make per stroke from
    Python (strace -c), where the command line answers them without a system
    call (process/getrusage_override.cpp), and their cost.

    PYTHONPATH=build/python python3 bench/python_throughput.py [-n 40] [--getrusage]
        [--timers-ab]    also libipopt's getrusage put back to the C library's, in
                         turns with bristle's rule (process/getrusage_hook.h)
        [--thumbnails]   also preset="thumbnail": speed and SSIM against the default
"""
import argparse
import ctypes
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "python", "examples"))

import numpy as np  # noqa: E402

import bristle  # noqa: E402
from bristle import _bristle, _options  # noqa: E402
from stroke_dataset import PX_PER_MM, random_stroke  # noqa: E402


def throughput(brush, trajs, threads, solver, **options):
    """Strokes/s, wall and CPU seconds of one render_many call, and its
    system time and minor page faults per stroke: what a run on one thread
    and a run on two may spend differently besides the solves, whose work
    (iterations) is the same on any thread count."""
    import resource
    before = resource.getrusage(resource.RUSAGE_SELF)
    start, cpu = time.perf_counter(), time.process_time()
    bristle.render_many(brush, trajs, threads=threads, px_per_mm=PX_PER_MM, solver=solver,
                        **options)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_SELF)
    n = len(trajs)
    kernel = (f"system {(after.ru_stime - before.ru_stime) / n * 1000:.1f} ms, "
              f"{(after.ru_minflt - before.ru_minflt) / n:.0f} page faults a stroke")
    return n / wall, wall, time.process_time() - cpu, kernel


def module_overhead(brush, trajs, solver):
    """CPU seconds per stroke of the whole bristle.render_stroke, and of the
    extension's call alone (the engine, the image handed over), each stroke
    on one thread (threads=1) so that process_time is this stroke's alone."""
    total = inner = 0.0
    for t in trajs:
        opts = _options.render_options("render", {"px_per_mm": PX_PER_MM, "solver": solver,
                                                  "threads": 1}, bristle.Error)
        b = time.process_time()
        _bristle.render_stroke(brush, t._t, opts)
        c = time.process_time()
        bristle.render_stroke(brush, t, px_per_mm=PX_PER_MM, solver=solver, threads=1)
        d = time.process_time()
        inner += c - b
        total += d - c
    return total / len(trajs), inner / len(trajs)


def wrapper_cost_s(brush, traj):
    """The package's own Python per render_stroke (option checks, the Stroke
    built from the extension's answer), the extension's call stubbed out."""
    opts = _options.render_options("render", {"px_per_mm": PX_PER_MM}, bristle.Error)
    answer = _bristle.render_stroke(brush, traj._t, opts)
    real = _bristle.render_stroke
    _bristle.render_stroke = lambda *args: answer
    try:
        n = 2000
        a = time.process_time()
        for _ in range(n):
            bristle.render_stroke(brush, traj, px_per_mm=PX_PER_MM, paint="sumi-ink")
        return (time.process_time() - a) / n
    finally:
        _bristle.render_stroke = real


def cli_cpu_per_stroke(made, bristle_bin, tmp):
    """CPU seconds (user + system) of `bristle render --threads 1` per data-set
    stroke, written as a depth CSV, less a stroke in the air's (the process's
    start, the brush read, the PNG written)."""
    import resource

    def run(xy, depth, tag):
        path = os.path.join(tmp, f"{tag}.csv")
        t = np.linspace(0, 0.3, len(depth))
        with open(path, "w") as f:
            f.write("# bristle-trajectory/1\nt_s,x_mm,y_mm,depth_mm,qw,qx,qy,qz\n")
            for k in range(len(depth)):
                f.write(f"{t[k]!r},{xy[k][0]!r},{xy[k][1]!r},{depth[k]!r},1,0,0,0\n")
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        subprocess.run([bristle_bin, "render", "-q", "--brush", "round", "--trajectory", path,
                        "--px-per-mm", str(PX_PER_MM), "--threads", "1", "-o",
                        os.path.join(tmp, f"{tag}.png")], check=True)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        return after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime
    air = min(run(made[0][0], np.full(len(made[0][1]), -5.0), f"air{k}") for k in range(3))
    total = sum(run(xy, depth, f"s{k}") for k, (xy, depth, _) in enumerate(made))
    return total / len(made) - air


def getrusage_cost_s():
    """One getrusage(RUSAGE_SELF) system call's time, from a tight loop."""
    libc = ctypes.CDLL("libc.so.6")
    buf = ctypes.create_string_buffer(256)
    n = 200000
    a = time.perf_counter()
    for _ in range(n):
        libc.getrusage(0, buf)
    loop = time.perf_counter() - a
    a = time.perf_counter()
    for _ in range(n):
        libc.getpid()  # the same ctypes call's cost without the kernel's rusage
    return max(loop - (time.perf_counter() - a), 0) / n


def getrusage_calls(count, seed, routed):
    """getrusage system calls of `count` strokes rendered in a child process,
    libipopt's getrusage routed to bristle's rule or not."""
    code = ("import sys; sys.path.insert(0, %r); import numpy as np, bristle; "
            "from stroke_dataset import random_stroke; rng = np.random.default_rng(%d); "
            "ts = [random_stroke(rng)[2] for _ in range(%d)]; b = bristle.Brush('round'); "
            "bristle._bristle._route_ipopt_getrusage(%r); "
            "[bristle.render(b, t, px_per_mm=2, threads=1) for t in ts]"
            % (os.path.join(HERE, "..", "python", "examples"), seed, count, routed))
    base = ("import sys; sys.path.insert(0, %r); import numpy as np, bristle; "
            "from stroke_dataset import random_stroke" % os.path.join(HERE, "..", "python", "examples"))
    calls = []
    for c in (code, base):
        r = subprocess.run(["strace", "-f", "-c", "-e", "trace=getrusage", sys.executable, "-c", c],
                           capture_output=True, text=True, env=os.environ)
        # "% time  seconds  usecs/call  calls  [errors]  syscall"
        line = [l.split() for l in r.stderr.splitlines() if l.split()[-1:] == ["getrusage"]]
        calls.append(int(line[0][3]) if line else 0)
    return calls[0] - calls[1]


# Coarser steps for thumbnails, against the default (docs/dynamics.md: a step
# is solved well when no hair root moves more than max_step_mm).
PRESETS = {
    "preset=thumbnail": {"preset": "thumbnail"},
    "max_step_mm=0.5": {"max_step_mm": 0.5, "min_rate_hz": 60},
    "max_step_mm=1": {"max_step_mm": 1.0, "min_rate_hz": 30},
    "steady_step_mm=0.5": {"steady_step_mm": 0.5},
}


def ssim(bristle_bin, a, b):
    r = subprocess.run([bristle_bin, "compare", "--json", a, b], capture_output=True, text=True)
    import json
    return json.loads(r.stdout)["ssim"]


def thumbnails(brush, trajs, bristle_bin, tmp):
    """CPU time and SSIM (luma, whole image) of each preset against the default."""
    def run(options, tag):
        cpu = time.process_time()
        imgs = bristle.render_many(brush, trajs, threads=1, px_per_mm=PX_PER_MM, **options)
        cpu = time.process_time() - cpu
        paths = []
        for i, img in enumerate(imgs):
            paths.append(os.path.join(tmp, f"{tag}-{i}.png"))
            bristle.save_png(paths[-1], img)
        return cpu, paths
    base_cpu, base = run({}, "default")
    print(f"thumbnails: default {base_cpu / len(trajs) * 1000:.0f} ms CPU a stroke")
    for k, (name, options) in enumerate(PRESETS.items()):
        cpu, paths = run(options, f"preset{k}")
        values = [ssim(bristle_bin, a, b) for a, b in zip(base, paths)]
        print(f"thumbnails: {name}: {cpu / len(trajs) * 1000:.0f} ms CPU a stroke "
              f"({base_cpu / cpu:.2f}x faster), SSIM against the default min {min(values):.4f} "
              f"mean {np.mean(values):.4f}")


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("-n", "--count", type=int, default=40)
    p.add_argument("--solver", default="ipopt", choices=("ipopt", "slsqp"))
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--getrusage", action="store_true", help="count Ipopt's timer calls (strace)")
    p.add_argument("--timers-ab", action="store_true",
                   help="also with libipopt's getrusage put back to the C library's")
    p.add_argument("--thumbnails", action="store_true",
                   help="coarser-step presets: speed and SSIM against the default")
    p.add_argument("--bristle", default=os.path.join(HERE, "..", "build", "cli", "bristle"),
                   help="the bristle executable, for `bristle compare --json`")
    a = p.parse_args()
    rng = np.random.default_rng(a.seed)
    made = [random_stroke(rng) for _ in range(a.count)]
    trajs = [m[2] for m in made]
    brush = bristle.Brush("round")
    # Warm up both threads' OSMesa contexts (llvmpipe compiles its shaders at
    # a context's first draw; render_many's second thread keeps borrowing the
    # one this call makes).
    bristle.render_many(brush, trajs[:2], threads=2, px_per_mm=PX_PER_MM)
    rates = {}
    for threads in (1, 2):
        for routed in ((False, True) if a.timers_ab else (True,)):
            _bristle._route_ipopt_getrusage(routed)
            rate, wall, cpu, kernel = throughput(brush, trajs, threads, a.solver)
            rates[threads, routed] = rate
            print(f"render_many threads={threads}{'' if routed else ' (Ipopt timers unrouted)'}: "
                  f"{a.count} strokes in {wall:.2f} s wall, {cpu:.2f} s CPU: {rate:.2f} strokes/s "
                  f"({cpu / a.count * 1000:.0f} ms CPU a stroke; {kernel})")
        if a.timers_ab:
            ratio = rates[threads, True] / rates[threads, False]
            print(f"threads={threads}: routed/unrouted {ratio:.2f}x")
    _bristle._route_ipopt_getrusage(True)
    if a.thumbnails:
        for threads in (1, 2):
            rate, wall, cpu, kernel = throughput(brush, trajs, threads, a.solver,
                                                 preset="thumbnail")
            rates[threads, "thumbnail"] = rate
            print(f"render_many threads={threads} preset=thumbnail: {a.count} strokes in "
                  f"{wall:.2f} s wall, {cpu:.2f} s CPU: {rate:.2f} strokes/s "
                  f"({cpu / a.count * 1000:.0f} ms CPU a stroke; {kernel})")
        print(f"preset=thumbnail: 2 threads over 1: "
              f"{rates[2, 'thumbnail'] / rates[1, 'thumbnail']:.2f}x")
    print(f"speed-up 2 threads over 1: {rates[2, True] / rates[1, True]:.2f}x"
          + (f" (unrouted {rates[2, False] / rates[1, False]:.2f}x)" if a.timers_ab else ""))
    some = trajs[: min(10, a.count)]
    total, inner = module_overhead(brush, some, a.solver)
    wrapper = wrapper_cost_s(brush, some[0])
    print(f"render_stroke: {total * 1000:.1f} ms CPU a stroke, the extension's call alone "
          f"{inner * 1000:.1f} ms (the difference is the solves' own spread); the package's "
          f"Python alone: {wrapper * 1e6:.0f} us a stroke ({wrapper / inner * 100:.3f} %)")
    import tempfile
    with tempfile.TemporaryDirectory() as tmp:
        cli = cli_cpu_per_stroke(made[: len(some)], a.bristle, tmp)
    print(f"bristle render --threads 1 on the same strokes: {cli * 1000:.1f} ms CPU a stroke "
          f"(its start-up taken off, but not the shaders llvmpipe compiles at the first draw of every process): the "
          f"module takes {abs(inner / cli - 1) * 100:.1f} % {'more' if inner > cli else 'less'} "
          f"(docs/python.md, \"Speed\")")
    if a.getrusage:
        n = min(5, a.count)
        calls = getrusage_calls(n, a.seed, False) / n
        cost = getrusage_cost_s()
        print(f"Ipopt's timers unrouted: {calls:.0f} getrusage calls a stroke at {cost * 1e6:.2f} "
              f"us each: {calls * cost * 1000:.1f} ms a stroke; routed (bristle.timers_patched="
              f"{bristle.timers_patched}): {getrusage_calls(n, a.seed, True) / n:.0f} a stroke")
    if a.thumbnails:
        import tempfile
        with tempfile.TemporaryDirectory() as tmp:
            thumbnails(brush, trajs, a.bristle, tmp)
    print(f"load average: {os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs")


if __name__ == "__main__":
    main()
