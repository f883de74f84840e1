"""Shared fixtures of the Python module's tests (docs/python.md, "Tests").

The tests import the build tree's package (PYTHONPATH=build/python, set by
python/tests/CMakeLists.txt) and run the build's `bristle` (BRISTLE_BIN) for
the pixels it is compared with. Strokes are small (2-4 px/mm, under half a
second of motion): the whole set stays within its CI time (docs/python.md).
"""
import os

import numpy as np
import pytest

import bristle

SOURCE_DIR = os.environ.get("BRISTLE_SOURCE_DIR",
                            os.path.join(os.path.dirname(__file__), "..", ".."))
BRISTLE_BIN = os.environ.get("BRISTLE_BIN", os.path.join(SOURCE_DIR, "build", "cli", "bristle"))


def pull(x0=10.0, y0=10.0, length_mm=10.0, depth_mm=2.0, duration_s=0.3, n=7):
    """Press depth_mm past first contact, pull length_mm along +x, lift: an
    upright round brush's short stroke, heights as press depths."""
    t = np.linspace(0.0, duration_s, n)
    x = x0 + np.linspace(0.0, length_mm, n)
    xy = np.stack([x, np.full(n, y0)], axis=1)
    depth = np.full(n, depth_mm)
    depth[0] = depth[-1] = -1.0  # in the air at both ends
    return bristle.Trajectory(t, xy, depth_mm=depth)


@pytest.fixture(scope="session")
def round_brush():
    return bristle.Brush("round")


@pytest.fixture(scope="session")
def short_pull():
    return pull()
