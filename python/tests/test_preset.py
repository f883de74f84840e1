"""preset="thumbnail": coarser simulation steps for small data-set images
(bristle/render.h, presetOptions; docs/python.md, "Presets"), close to the
default's strokes and the same as `bristle render --preset thumbnail`."""
import json
import os
import subprocess
import sys

import numpy as np
import pytest

import bristle
from conftest import BRISTLE_BIN, SOURCE_DIR
from test_cli_pixels import cli_render, same_pixels, short_csv

sys.path.insert(0, os.path.join(SOURCE_DIR, "python", "examples"))
from stroke_dataset import PX_PER_MM, random_stroke  # noqa: E402

# The preset is kept only while its strokes stay this close to the default's
# (luma SSIM of the whole image, `bristle compare`): over 56 data-set strokes
# the least was 0.955 (docs/PERFORMANCE.md, "A thumbnail preset").
MIN_SSIM = 0.95


def ssim(tmp_path, a, b):
    pa, pb = tmp_path / "a.png", tmp_path / "b.png"
    bristle.save_png(pa, a)
    bristle.save_png(pb, b)
    run = subprocess.run([BRISTLE_BIN, "compare", "--json", str(pa), str(pb)],
                         capture_output=True, text=True)
    return json.loads(run.stdout)["ssim"]


def test_thumbnail_strokes_stay_close_to_the_default(tmp_path, round_brush):
    rng = np.random.default_rng(3)
    trajs = [random_stroke(rng)[2] for _ in range(3)]
    default = bristle.render_many(round_brush, trajs, px_per_mm=PX_PER_MM)
    thumb = bristle.render_many(round_brush, trajs, px_per_mm=PX_PER_MM, preset="thumbnail")
    for a, b in zip(default, thumb):
        assert a.shape == b.shape
        assert not np.array_equal(a, b), "the preset changed no step"
        assert ssim(tmp_path, a, b) >= MIN_SSIM


def test_an_option_given_by_name_wins_over_the_preset(round_brush, short_pull):
    preset = bristle.preset_options("thumbnail")
    both = bristle.render(round_brush, short_pull, px_per_mm=2, preset="thumbnail",
                          max_step_mm=0.5)
    named = bristle.render(round_brush, short_pull, px_per_mm=2, max_step_mm=0.5,
                           min_rate_hz=preset["min_rate_hz"],
                           steady_step_mm=preset["steady_step_mm"],
                           ipopt_options=preset["ipopt_options"])
    assert np.array_equal(both, named)
    assert np.array_equal(bristle.render(round_brush, short_pull, px_per_mm=2, preset="default"),
                          bristle.render(round_brush, short_pull, px_per_mm=2))


def test_the_command_lines_preset_paints_the_same_pixels(tmp_path, round_brush):
    csv = short_csv(tmp_path)
    cli = cli_render(tmp_path, ["--brush", "round", "--trajectory", str(csv), "--px-per-mm", "2",
                                "--preset", "thumbnail"])
    img = bristle.render(round_brush, bristle.Trajectory.load(csv), px_per_mm=2,
                         preset="thumbnail")
    ok, said = same_pixels(tmp_path, cli, img)
    assert ok, said


@pytest.mark.parametrize("value, said", [
    ("poster", "render: preset poster: unknown (known: default, thumbnail)"),
    (3, "render: preset: must be a str"),
])
def test_an_unknown_preset_is_an_error(round_brush, short_pull, value, said):
    with pytest.raises(bristle.Error) as e:
        bristle.render(round_brush, short_pull, preset=value)
    assert str(e.value) == said and e.value.exit_code == 64


def test_the_preset_loosens_ipopts_tolerance_and_an_option_given_wins(round_brush, short_pull):
    # The thumbnail preset's tol=1e-4 (docs/PERFORMANCE.md, "Where a
    # thumbnail's iterations go"); ipopt_options given by name replace it.
    assert bristle.preset_options("thumbnail")["ipopt_options"] == ["tol=1e-4"]
    assert bristle.preset_options("default")["ipopt_options"] == []
    given = bristle.render(round_brush, short_pull, px_per_mm=2, preset="thumbnail",
                           ipopt_options=["tol=1e-8"])
    steps_only = bristle.render(round_brush, short_pull, px_per_mm=2,
                                **{k: v for k, v in bristle.preset_options("thumbnail").items()
                                   if k != "ipopt_options"})
    assert np.array_equal(given, steps_only)


@pytest.mark.parametrize("value", ["tol=1e-4", [3], ["tol=abc"], ["not_an_option=1"]])
def test_a_bad_ipopt_option_is_an_error(round_brush, short_pull, value):
    with pytest.raises(bristle.Error) as e:
        bristle.render(round_brush, short_pull, ipopt_options=value)
    assert e.value.exit_code == 64 and "ipopt_option" in str(e.value)
