"""Ipopt 3.11's timers inside Python: libipopt's getrusage slot goes to
bristle's rule (process/getrusage_hook.h), so a solve asks the kernel for no
CPU time, as the command line's solves do (docs/python.md, "Speed")."""
import os
import shutil
import subprocess
import sys

import pytest

import bristle
from bristle import _bristle


def test_libipopt_getrusage_goes_to_bristles_rule():
    assert bristle.timers_patched is True
    # Ipopt's own clock, read through libipopt's binding inside a solve's
    # scope, is answered by the rule (counted on this thread), not the kernel.
    assert _bristle._ipopt_clock_read_skipped()


def test_the_c_librarys_getrusage_can_be_put_back():
    try:
        assert _bristle._route_ipopt_getrusage(False)
        assert not _bristle._ipopt_clock_read_skipped()
    finally:
        assert _bristle._route_ipopt_getrusage(True)
    assert _bristle._ipopt_clock_read_skipped()


STROKE = ("import numpy as np, bristle; t = np.linspace(0, 0.3, 7); "
          "xy = np.stack([10 + np.linspace(0, 10, 7), np.full(7, 10.0)], axis=1); "
          "d = np.full(7, 2.0); d[0] = d[-1] = -1.0; "
          "tr = bristle.Trajectory(t, xy, depth_mm=d); {}"
          "bristle.render(bristle.Brush('round'), tr, px_per_mm=2, threads=1, solver='ipopt')")


def getrusage_calls(code):
    """getrusage system calls of a child Python running `code` (strace -c)."""
    r = subprocess.run(["strace", "-f", "-c", "-e", "trace=getrusage", sys.executable, "-c", code],
                       capture_output=True, text=True, env=os.environ, timeout=120)
    assert r.returncode == 0, r.stderr[-2000:]
    rows = [line.split() for line in r.stderr.splitlines()]
    found = [int(row[3]) for row in rows if row[-1:] == ["getrusage"]]
    return found[0] if found else 0


@pytest.mark.skipif(shutil.which("strace") is None, reason="needs strace")
def test_a_solve_from_python_makes_no_getrusage_system_call():
    routed = getrusage_calls(STROKE.format(""))
    # The same stroke with libipopt's slot put back to the C library: Ipopt's
    # timers read the CPU time 100-300 times an iteration (ipopt_timers.h).
    plain = getrusage_calls(STROKE.format("bristle._bristle._route_ipopt_getrusage(False); "))
    assert plain > 1000, f"the unrouted stroke made only {plain} calls: is Ipopt solving?"
    # Nothing but Ipopt calls getrusage in a render: routed, none remain.
    assert routed == 0, f"{routed} getrusage system calls with libipopt routed ({plain} without)"
