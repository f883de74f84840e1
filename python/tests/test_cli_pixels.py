"""The same inputs and options give `bristle render`'s pixels byte for byte
(docs/python.md, "The same pixels as the command line"): the module installs
the command line's KKT solver at import (docs/api.md, "Process-wide set-up")."""
import json
import os
import subprocess

import numpy as np
import pytest

import bristle
from conftest import BRISTLE_BIN, SOURCE_DIR


def cli_render(tmp_path, args):
    out = tmp_path / "cli.png"
    env = {k: v for k, v in os.environ.items() if k != "GALLIUM_DRIVER"}
    run = subprocess.run([BRISTLE_BIN, "render", "-q", *args, "-o", str(out)],
                         capture_output=True, text=True, env=env)
    assert run.returncode == 0, run.stderr
    return out


def same_pixels(tmp_path, cli_png, image):
    ours = tmp_path / "python.png"
    bristle.save_png(ours, image)
    cmp = subprocess.run([BRISTLE_BIN, "compare", str(cli_png), str(ours)],
                         capture_output=True, text=True)
    return cmp.returncode == 0 and "identical pixels" in cmp.stdout, cmp.stdout + cmp.stderr


def short_csv(tmp_path, rows=50):
    """The first rows of the round's straight pull: pressed and pulling."""
    src = os.path.join(SOURCE_DIR, "scenes", "trajectories", "straight-pull.csv")
    with open(src) as f:
        lines = f.readlines()
    header = [i for i, l in enumerate(lines) if l.startswith("t_s")][0]
    path = tmp_path / "short.csv"
    path.write_text("".join(lines[: header + 1 + rows]))
    return path


def test_a_csv_trajectory_renders_the_clis_pixels(tmp_path):
    csv = short_csv(tmp_path)
    cli = cli_render(tmp_path, ["--brush", "round", "--trajectory", str(csv),
                                "--px-per-mm", "3", "--paint", "ultramarine"])
    img = bristle.render(bristle.Brush("round"), bristle.Trajectory.load(csv), px_per_mm=3,
                         paint="ultramarine")
    ok, said = same_pixels(tmp_path, cli, img)
    assert ok, said


def test_arrays_equal_to_the_csv_render_the_clis_pixels(tmp_path):
    csv = short_csv(tmp_path, rows=40)
    rows = [l for l in csv.read_text().splitlines() if l and not l.startswith("#")]
    header = rows[0].split(",")
    data = np.array([[float(v) for v in r.split(",")] for r in rows[1:]])
    col = {name: data[:, i] for i, name in enumerate(header)}
    t = bristle.Trajectory(col["t_s"], np.stack([col["x_mm"], col["y_mm"], col["z_mm"]], 1),
                           np.stack([col["qw"], col["qx"], col["qy"], col["qz"]], 1))
    cli = cli_render(tmp_path, ["--brush", "round", "--trajectory", str(csv),
                                "--px-per-mm", "2", "--load", "tip",
                                "--paint", "burnt-umber,cadmium-red"])
    img = bristle.render(bristle.Brush("round"), t, px_per_mm=2, load="tip",
                         paint="burnt-umber,cadmium-red")
    ok, said = same_pixels(tmp_path, cli, img)
    assert ok, said


def test_recordings_load_with_a_brush_and_render_the_clis_pixels(tmp_path):
    # What `render --trajectory` reads besides its own CSV: a Pointer Events
    # recording and an SVG's paths, imported for the brush (docs/input.md).
    # Each note the command line prints as a warning is a RecordingWarning:
    # the recording merges samples of repeated times, the SVG's <text> is
    # skipped.
    brush = bristle.Brush("round")
    for name, note in [("pointer-events.csv", "merged"), ("three-strokes.svg", "<text>")]:
        path = os.path.join(SOURCE_DIR, "scenes", "recordings", name)
        with pytest.warns(bristle.RecordingWarning, match=note):
            t = bristle.Trajectory.load(path, brush)
        cli = cli_render(tmp_path, ["--brush", "round", "--trajectory", path, "--px-per-mm", "2"])
        img = bristle.render(brush, t, px_per_mm=2)
        ok, said = same_pixels(tmp_path, cli, img)
        assert ok, f"{name}: {said}"


def test_a_recording_without_a_brush_is_refused_naming_the_format_rule():
    # Without a brush there is no mapping from pen pressure to press depth.
    path = os.path.join(SOURCE_DIR, "scenes", "recordings", "pointer-events.csv")
    with pytest.raises(bristle.Error) as e:
        bristle.Trajectory.load(path)
    assert e.value.exit_code == 65
    assert "line 1: the first line must be '# bristle-trajectory/1'" in e.value.message


def test_a_scene_renders_the_clis_pixels(tmp_path):
    # A painting of two strokes, the second laid beside the first's wet paint
    # and meeting it (docs/scene-format.md): render_scene paints what
    # `bristle render SCENE` paints, byte for byte.
    short = short_csv(tmp_path, rows=80)  # pressed, then pulled 9 mm along +x
    brush = os.path.join(SOURCE_DIR, "scenes", "brushes", "round.json")
    scene = {
        "format": "bristle-scene/1", "name": "crossing",
        "canvas": {"size_mm": [40, 30], "px_per_mm": 3},
        "strokes": [
            {"brush": brush, "trajectory": str(short), "paint": {"paints": ["ultramarine"]},
             "placement": {"offset_mm": [0, -5]}},  # y = 15, x 12 to 21
            {"brush": brush, "trajectory": str(short), "paint": {"paints": ["cadmium-red"]},
             "placement": {"offset_mm": [36, 0], "rotate_deg": 90}},  # x = 16, y 12 to 21
        ],
    }
    path = tmp_path / "scene.json"
    path.write_text(json.dumps(scene))
    env = {k: v for k, v in os.environ.items() if k != "GALLIUM_DRIVER"}
    cli = tmp_path / "cli.png"
    run = subprocess.run([BRISTLE_BIN, "render", "-q", str(path), "-o", str(cli)],
                         capture_output=True, text=True, env=env)
    assert run.returncode == 0, run.stderr
    painting = bristle.render_scene(path)
    assert painting.image.shape == (90, 120, 3)
    assert painting.untouched == []
    assert painting.paint_laid_mm3 > 0
    ok, said = same_pixels(tmp_path, cli, painting.image)
    assert ok, said


def test_a_bad_scene_raises_the_clis_message(tmp_path):
    path = tmp_path / "scene.json"
    path.write_text('{"format": "bristle-scene/1", "name": "x", "canvas": {"size_mm": [40, 30], '
                    '"px_per_mm": 3}, "strokes": []}')
    with pytest.raises(bristle.Error) as e:
        bristle.render_scene(path)
    assert e.value.exit_code == 65
    assert str(path) in e.value.message and "/strokes" in e.value.message
    with pytest.raises(bristle.Error, match="SceneOptions.threads 3: must be in"):
        bristle.render_scene(path, threads=3)
