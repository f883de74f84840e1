"""render_many: strokes on several threads with the GIL released give the
same pixels as on one (docs/python.md, "Threads")."""
import threading
import time

import numpy as np

import bristle
from bristle import _bristle
from conftest import pull


def strokes():
    # Four short pulls at different places, depths and lengths.
    return [pull(x0=5 + 3 * i, y0=8 + 2 * i, length_mm=6 + 2 * i, depth_mm=1 + i, n=5)
            for i in range(4)]


def test_two_threads_paint_one_threads_pixels(round_brush):
    trajs = strokes()
    one = bristle.render_many(round_brush, trajs, threads=1, px_per_mm=2)
    two = bristle.render_many(round_brush, trajs, threads=2, px_per_mm=2)
    assert len(one) == len(two) == 4
    for a, b in zip(one, two):
        assert a.shape == b.shape and np.array_equal(a, b)
    # and the same as render(), one stroke alone
    assert np.array_equal(one[3], bristle.render(round_brush, trajs[3], px_per_mm=2))


def test_a_failing_stroke_names_its_index(round_brush):
    # 9000 mm at 2 px/mm: a canvas beyond the 16384 px limit, refused before
    # anything is simulated.
    trajs = strokes()[:2] + [pull(length_mm=9000)]
    try:
        bristle.render_many(round_brush, trajs, threads=2, px_per_mm=2)
    except bristle.Error as e:
        assert str(e).startswith("render_many: stroke 2: "), str(e)
    else:
        raise AssertionError("no error for a stroke beyond the canvas limits")


def test_python_threads_run_while_a_stroke_renders(round_brush):
    # A Python thread notes the time every millisecond. Were the GIL held
    # through the engine's work, it could note none in the middle of the
    # render (the package's own Python, where it might, is microseconds at
    # the ends of a call of a tenth of a second or more).
    stamps = []
    done = threading.Event()

    def clock():
        while not done.is_set():
            stamps.append(time.perf_counter())
            time.sleep(0.001)

    th = threading.Thread(target=clock)
    th.start()
    try:
        start = time.perf_counter()
        bristle.render(round_brush, pull(n=9, duration_s=0.4), px_per_mm=2)
        end = time.perf_counter()
    finally:
        done.set()
        th.join()
    quarter = (end - start) / 4
    middle = [t for t in stamps if start + quarter < t < end - quarter]
    assert middle, f"no stamp in the middle half of a {end - start:.3f} s render"


def test_render_many_lends_its_contexts_to_the_next_call(round_brush):
    # render_many's second thread draws on an OSMesa context an earlier call
    # made: one made per call would compile llvmpipe's shaders again, about
    # 130 ms of CPU a call (docs/python.md, "Speed"). The same pixels on it.
    trajs = strokes()[:2]
    bristle.render_many(round_brush, trajs, threads=2, px_per_mm=2)
    made = _bristle._lent_renderers_made()
    assert made >= 1
    again = bristle.render_many(round_brush, trajs, threads=2, px_per_mm=2)
    assert _bristle._lent_renderers_made() == made
    for a, t in zip(again, trajs):
        assert np.array_equal(a, bristle.render(round_brush, t, px_per_mm=2))
