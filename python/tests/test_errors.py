"""Bad input is a bristle.Error naming the argument and the rule, with the
command line's exit code (docs/errors.md); never a crash, nothing on stderr."""
import math

import numpy as np
import pytest

import bristle
from conftest import pull

Q = (1.0, 0.0, 0.0, 0.0)
T3 = [0.0, 0.1, 0.2]
XYZ3 = [[0, 0, 25], [1, 0, 25], [2, 0, 25]]


def brush():
    return bristle.Brush("round")


# (what is called, exit code, words the message must contain)
CASES = {
    "unknown brush": (lambda: bristle.Brush("no-such-brush"), 66, ["no-such-brush", "library"]),
    "brush not a str": (lambda: bristle.Brush(3), 64, ["name_or_path", "str"]),
    "missing csv": (lambda: bristle.Trajectory.load("/nonexistent/t.csv"), 66, ["t.csv"]),
    "t_s 2-D": (lambda: bristle.Trajectory([[0, 1]], XYZ3), 64, ["t_s", "shape"]),
    "xyz wrong shape": (lambda: bristle.Trajectory(T3, [[0, 0], [1, 0], [2, 0]]), 64,
                        ["xyz_mm", "(3, 3)"]),
    "xyz rows differ": (lambda: bristle.Trajectory(T3, XYZ3[:2]), 64, ["xyz_mm", "shape"]),
    "complex dtype": (lambda: bristle.Trajectory(np.array(T3) * 1j, XYZ3), 64,
                      ["t_s", "complex128"]),
    "strings": (lambda: bristle.Trajectory(["a", "b", "c"], XYZ3), 64, ["t_s", "real"]),
    "ragged": (lambda: bristle.Trajectory(T3, [[0, 0, 1], [1, 0], [2]]), 64, ["xyz_mm"]),
    "NaN position": (lambda: bristle.Trajectory(T3, [[0, 0, 25], [math.nan, 0, 25], [2, 0, 25]]),
                     65, ["xyz_mm[1]", "finite"]),
    "times repeat": (lambda: bristle.Trajectory([0, 0.1, 0.1], XYZ3), 65,
                     ["t_s[2]", "increase strictly"]),
    "zero quaternion": (lambda: bristle.Trajectory(T3, XYZ3, [[1, 0, 0, 0], [0, 0, 0, 0],
                                                              [1, 0, 0, 0]]), 65,
                        ["quaternion_wxyz[1]", "zero norm"]),
    "one sample": (lambda: bristle.Trajectory([0], [[0, 0, 0]]), 65, ["at least 2"]),
    "depth shape": (lambda: bristle.Trajectory(T3, [[0, 0]] * 3, depth_mm=[1, 2]), 64,
                    ["depth_mm", "shape"]),
    "unknown option": (lambda: bristle.render(brush(), pull(), colour="red"), 64,
                       ["colour", "known"]),
    "px_per_mm range": (lambda: bristle.render(brush(), pull(), px_per_mm=1000), 64,
                        ["px_per_mm", "[0.5, 100]"]),
    "px_per_mm NaN": (lambda: bristle.render(brush(), pull(), px_per_mm=math.nan), 64,
                      ["px_per_mm"]),
    "px_per_mm str": (lambda: bristle.render(brush(), pull(), px_per_mm="8"), 64,
                      ["px_per_mm", "real number"]),
    "unknown paint": (lambda: bristle.render(brush(), pull(), paint="no-such-pigment"), 65,
                      ["paint", "no-such-pigment"]),
    "bad solver": (lambda: bristle.render(brush(), pull(), solver="newton"), 64,
                   ["solver", "ipopt"]),
    "not a brush": (lambda: bristle.render("round", pull()), 64, ["brush", "bristle.Brush"]),
    "not a trajectory": (lambda: bristle.render(brush(), [0, 1]), 64, ["trajectory"]),
    "canvas too large": (lambda: bristle.Canvas((10000, 10000), px_per_mm=100), 64,
                         ["16384"]),
    "canvas size": (lambda: bristle.Canvas(10), 64, ["size_mm"]),
    "sim time back": (lambda: step_twice(0.2, 0.1), 64, ["t_s", "after"]),
    "sim zero quaternion": (lambda: bristle.Simulation(brush()).step([0, 0, 30], [0, 0, 0, 0]),
                            64, ["quaternion_wxyz", "zero norm"]),
    "sim position shape": (lambda: bristle.Simulation(brush()).step([0, 0]), 64,
                           ["position_mm", "(3,)"]),
    "sim solver": (lambda: bristle.Simulation(brush(), solver="x"), 64, ["solver"]),
    "render_many counts": (lambda: bristle.render_many([brush()] * 2, [pull()]), 64,
                           ["brushes", "one per trajectory"]),
    "save_png dtype": (lambda: bristle.save_png("/tmp/x.png", np.zeros((2, 2, 3))), 64,
                       ["uint8"]),
    "save_png folder": (lambda: bristle.save_png("/nonexistent/x.png",
                                                 np.zeros((2, 2, 3), np.uint8)), 73,
                        ["/nonexistent/x.png"]),
}


def step_twice(t1, t2):
    sim = bristle.Simulation(brush())
    sim.step([0, 0, 30], t_s=t1)
    sim.step([0, 0, 30], t_s=t2)


@pytest.mark.parametrize("name", sorted(CASES))
def test_bad_input_is_one_error_naming_the_rule(name, capfd):
    call, code, words = CASES[name]
    with pytest.raises(bristle.Error) as e:
        call()
    message = str(e.value)
    assert "\n" not in message
    for w in words:
        assert w in message, f"{w!r} not in {message!r}"
    assert e.value.exit_code == code, message
    assert e.value.category == bristle.Error.CATEGORIES[code]
    out, err = capfd.readouterr()
    assert out == "" and err == ""


def rss_kib():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * 4


def test_ten_thousand_failing_calls_do_not_grow_the_process():
    b = brush()
    good = pull()
    failing = [
        lambda: bristle.Brush("no-such-brush"),
        lambda: bristle.Trajectory(T3, [[0, 0, 25], [math.nan, 0, 25], [2, 0, 25]]),
        lambda: bristle.render(b, good, px_per_mm=1000),
        lambda: bristle.render(b, good, paint="no-such-pigment"),
    ]

    def run(n):
        for i in range(n):
            try:
                failing[i % len(failing)]()
            except bristle.Error:
                pass
    run(1000)  # the allocator's and interpreter's caches reach their size
    before = rss_kib()
    run(10000)
    growth = rss_kib() - before
    # A leak of a message string or an exception object per call (>= 100
    # bytes) would grow the process by >= 1000 KiB over 10,000 calls; the
    # allocator's own noise on this machine stays within a few hundred KiB.
    assert growth < 1000, f"RSS grew {growth} KiB over 10,000 failing calls"
