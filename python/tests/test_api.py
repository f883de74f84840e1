"""The module's API: brushes, trajectories, render, Canvas, PNG files."""
import os
import subprocess

import numpy as np
import pytest

import bristle
from conftest import BRISTLE_BIN, SOURCE_DIR, pull


def test_brush_by_name_has_the_libraries_facts(round_brush):
    assert round_brush.name == "round"
    assert round_brush.spine_count == 7
    assert round_brush.path.endswith(os.path.join("brushes", "round.json"))
    # The longest spine of round.json: segments 6 + 5.5 + 5 + 3.5 mm.
    assert round_brush.hair_length_mm == pytest.approx(20.0, abs=1e-9)
    assert round_brush.reach_mm >= round_brush.hair_length_mm


def test_brush_by_path_is_the_same_brush(round_brush):
    b = bristle.Brush(os.path.join(SOURCE_DIR, "scenes", "brushes", "round.json"))
    assert b.name == round_brush.name and b.spine_count == round_brush.spine_count


def test_trajectory_from_arrays_and_from_a_file():
    t = bristle.Trajectory([0, 0.1, 0.2], [[0, 0, 25], [1, 0, 25], [2, 0, 25]])
    assert len(t) == 3 and t.start_s == 0 and t.end_s == pytest.approx(0.2)
    assert not t.has_depths
    f = bristle.Trajectory.load(os.path.join(SOURCE_DIR, "scenes/trajectories/s-curve.csv"))
    assert f.sample_count > 100 and f.start_s == 0
    assert pull().has_depths


def test_float32_and_integer_arrays_are_taken():
    t = bristle.Trajectory(np.array([0, 1], dtype=np.int32),
                           np.zeros((2, 3), dtype=np.float32), np.array([1, 0, 0, 0]))
    assert len(t) == 2


def test_render_is_an_owning_uint8_image_with_paint(round_brush, short_pull):
    s = bristle.render_stroke(round_brush, short_pull, px_per_mm=2, paint="ultramarine")
    img = s.image
    assert img.dtype == np.uint8 and img.ndim == 3 and img.shape[2] == 3
    assert img.flags["C_CONTIGUOUS"]
    # The canvas: everything the brush reaches plus a 5 mm margin on each side,
    # at least the 10 mm pull + 2 x 5 mm wide.
    assert img.shape[1] >= 20 * 2
    assert s.touched and s.ink_pixels > 0 and s.paint_laid_mm3 > 0
    assert s.failed_spine_solves == 0
    # Ultramarine is blue: the darkest pixel has more blue than red.
    darkest = img.reshape(-1, 3)[img.sum(axis=2).argmin()]
    assert int(darkest[2]) > int(darkest[0])
    # The corner is bare paper (#f6f1e6).
    assert tuple(img[0, 0]) == (0xF6, 0xF1, 0xE6)


def test_a_stroke_in_the_air_leaves_no_paint(round_brush):
    s = bristle.render_stroke(round_brush, pull(depth_mm=-3.0), px_per_mm=2)
    assert not s.touched and s.ink_pixels == 0


def test_canvas_strokes_accumulate_and_save(round_brush, tmp_path):
    canvas = bristle.Canvas(size_mm=(40, 30), px_per_mm=2)
    assert canvas.image().shape == (60, 80, 3)
    bare = canvas.image().copy()
    facts = canvas.stroke(round_brush, pull(x0=10, y0=10), paint="sumi-ink")
    assert facts.touched
    one = canvas.image()
    canvas.dry()
    canvas.stroke(round_brush, pull(x0=10, y0=20), paint="sumi-ink")
    two = canvas.image()
    changed = lambda a, b: int((a != b).any(axis=2).sum())
    assert changed(bare, one) > 0 and changed(one, two) > 0
    path = tmp_path / "c.png"
    canvas.save(path)
    assert path.stat().st_size > 0


def test_save_png_of_render_reads_back_in_bristle_compare(round_brush, short_pull, tmp_path):
    img = bristle.render(round_brush, short_pull, px_per_mm=2)
    bristle.save_png(tmp_path / "a.png", img)
    bristle.save_png(tmp_path / "b.png", img)
    out = subprocess.run([BRISTLE_BIN, "compare", str(tmp_path / "a.png"),
                          str(tmp_path / "b.png")], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert "identical pixels" in out.stdout
