"""bristle: physically based brush strokes (Baxter & Lin 2004) from Python.

    import numpy as np, bristle
    brush = bristle.Brush("round")
    traj = bristle.Trajectory(t_s, xy_mm, depth_mm=depth_mm)
    img = bristle.render(brush, traj, px_per_mm=8, paint="ultramarine")  # H x W x 3 uint8

Units are in the names (_mm, _s, _n, _px). Every failure is a bristle.Error
with the command line's one-line message and exit code (docs/python.md).
"""
import os as _os
import types as _types
import warnings as _warnings

import numpy as _np


class Error(Exception):
    """bristle's one exception: a one-line message naming the argument (or
    file and field) and the rule it broke, and the exit code `bristle` would
    give for the same problem (docs/errors.md).

    exit_code: 64 usage, 65 data error, 66 no input, 70 software,
               73 cannot create, 74 I/O error; category: its name.
    """

    CATEGORIES = {64: "usage", 65: "data", 66: "no-input", 70: "software",
                  73: "cant-create", 74: "io"}

    def __init__(self, message, exit_code=64):
        super().__init__(message)
        self.message = message
        self.exit_code = int(exit_code)
        self.category = self.CATEGORIES.get(self.exit_code, "software")


class RecordingWarning(UserWarning):
    """What importing a pen recording notes without refusing it (samples
    merged, SVG elements skipped), as the command line's warnings."""


from . import _bristle  # noqa: E402  (Error first: the extension raises it)
from . import _options  # noqa: E402
from . import _paths  # noqa: E402

_bristle._set_error_class(Error)
__version__ = _bristle.__version__
# True when Ipopt's timers answer without a system call inside a solve, as in
# the command line (docs/python.md, "Speed"); False: the same strokes, slower.
timers_patched = _bristle._timers_patched

# Library names resolve in this build's or install's share/bristle/brushes,
# then in BRISTLE_BRUSH_PATH's folders, as for the `bristle` beside it.
_bristle.set_brush_library_dirs(_paths.brush_library_dirs(_os.path.dirname(__file__)))

Brush = _bristle.Brush
set_brush_library_dirs = _bristle.set_brush_library_dirs


def _real_array(where, name, value, tail, rows=None):
    """value as a C-contiguous float64 array of shape (rows, *tail), or an Error."""
    try:
        a = _np.asarray(value)
    except Exception:  # an object numpy cannot make an array of
        raise Error(f"{where}: {name}: must be an array of real numbers", 64) from None
    if a.dtype.kind not in "iuf":
        raise Error(f"{where}: {name}: must be an array of real numbers, not dtype {a.dtype}", 64)
    want = (rows if rows is not None else "N",) + tuple(tail)
    shape_ok = a.ndim == len(want) and tuple(a.shape[1:]) == tuple(tail)
    if not shape_ok or (rows is not None and a.shape[0] != rows):
        shown = "(" + ", ".join(str(d) for d in want) + (",)" if len(want) == 1 else ")")
        raise Error(f"{where}: {name}: shape {a.shape}: must be {shown}", 64)
    return _np.ascontiguousarray(a, dtype=_np.float64)


def _quaternions(where, quaternion_wxyz, n):
    """(N, 4) rotations; one (4,) quaternion stands for all N; None is upright."""
    if quaternion_wxyz is None:
        quaternion_wxyz = (1.0, 0.0, 0.0, 0.0)
    try:
        a = _np.asarray(quaternion_wxyz)
    except Exception:  # ragged: _real_array names it
        a = None
    if a is not None and a.shape == (4,) and a.dtype.kind in "iuf":
        quaternion_wxyz = _np.broadcast_to(a, (n, 4))
    return _real_array(where, "quaternion_wxyz", quaternion_wxyz, (4,), n)


class Trajectory:
    """The motion of a brush's handle (the ferrule): times, positions, rotations.

    Trajectory(t_s, xyz_mm, quaternion_wxyz=None): t_s (N,) strictly increasing
    seconds; xyz_mm (N, 3) canvas mm (x right, y up, z above the paper);
    quaternion_wxyz (N, 4) or (4,) unit quaternions w, x, y, z (None: upright).
    Trajectory(t_s, xy_mm, quaternion_wxyz, depth_mm=d): heights as press depth past
    the brush's first contact (mm, positive into the paper); xy_mm is (N, 2).
    Trajectory.load(path): a bristle-trajectory/1 CSV file, as `bristle render
    --trajectory` reads it.
    """

    def __init__(self, t_s, xyz_mm, quaternion_wxyz=None, *, depth_mm=None):
        where = "Trajectory"
        t = _real_array(where, "t_s", t_s, ())
        n = t.shape[0]
        q = _quaternions(where, quaternion_wxyz, n)
        if depth_mm is None:
            xyz = _real_array(where, "xyz_mm", xyz_mm, (3,), n)
            self._t = _bristle.Trajectory.from_arrays(t, xyz, q)
        else:
            xy = _real_array(where, "xy_mm (with depth_mm)", xyz_mm, (2,), n)
            depth = _real_array(where, "depth_mm", depth_mm, (), n)
            self._t = _bristle.Trajectory.from_depth(t, xy, depth, q)

    @classmethod
    def load(cls, path, brush=None):
        """A bristle-trajectory/1 CSV file (docs/formats.md, "Trajectory").

        With a brush, also what `bristle render --trajectory` reads: a pen
        recording (MyPaint events, a Pointer Events CSV, an SVG's paths;
        docs/input.md) imported with bristle import's default mapping for
        that brush. What the import notes (samples merged, SVG elements
        skipped) is issued as a bristle.RecordingWarning."""
        if not isinstance(path, (str, _os.PathLike)):
            raise Error("Trajectory.load: path: must be a str or os.PathLike", 64)
        self = cls.__new__(cls)
        if brush is None:
            self._t = _bristle.Trajectory.load(_os.fspath(path))
            return self
        self._t, notes = _bristle.Trajectory.load_for(_os.fspath(path),
                                                      _brush("Trajectory.load", brush))
        for note in notes:
            _warnings.warn(note, RecordingWarning, stacklevel=2)
        return self

    sample_count = property(lambda self: self._t.sample_count, doc="samples")
    start_s = property(lambda self: self._t.start_s, doc="first sample's time (s)")
    end_s = property(lambda self: self._t.end_s, doc="last sample's time (s)")
    has_depths = property(lambda self: self._t.has_depths,
                          doc="heights are press depths, placed for each brush")

    def __len__(self):
        return self._t.sample_count

    def __repr__(self):
        return (f"bristle.Trajectory({self.sample_count} samples, "
                f"{self.start_s:g} to {self.end_s:g} s)")


def _brush(where, brush):
    if not isinstance(brush, Brush):
        raise Error(f"{where}: brush: must be a bristle.Brush, not {type(brush).__name__}", 64)
    return brush


def _trajectory(where, trajectory):
    if not isinstance(trajectory, Trajectory):
        raise Error(f"{where}: trajectory: must be a bristle.Trajectory, "
                    f"not {type(trajectory).__name__}", 64)
    return trajectory._t


class Stroke(_types.SimpleNamespace):
    """A rendered stroke: image (H, W, 3) uint8 sRGB, row 0 at the top;
    x0_mm, y0_mm (the image's lower-left corner on the canvas) and px_per_mm;
    touched, ink_pixels, paint_laid_mm3, failed_spine_solves."""


class Painting(_types.SimpleNamespace):
    """A rendered scene: image (H, W, 3) uint8 sRGB of the scene's whole
    canvas, row 0 at the top; x0_mm, y0_mm and px_per_mm; paint_laid_mm3,
    paint_picked_up_mm3, untouched (the strokes, from 0, whose brush never
    touched the paper), failed_spine_solves."""


def render_scene(path, impasto=False, solver_max_iterations=200, threads=0):
    """A bristle-scene/1 file (docs/scene-format.md): its strokes painted in
    order on its own canvas, with its brushes, paints and paper, the pixels
    of `bristle render SCENE -o out.png` with the same options (a Painting).
    The scene sets everything else; the GIL is released while it paints."""
    where = "render_scene"
    if not isinstance(path, (str, _os.PathLike)):
        raise Error(f"{where}: path: must be a str or os.PathLike", 64)
    if not isinstance(impasto, bool):
        raise Error(f"{where}: impasto: must be True or False", 64)
    for name, value in (("solver_max_iterations", solver_max_iterations), ("threads", threads)):
        if isinstance(value, bool) or not isinstance(value, int):
            raise Error(f"{where}: {name}: must be an int", 64)
    image, facts = _bristle.render_scene(_os.fspath(path), impasto, solver_max_iterations,
                                         threads)
    return Painting(image=image, **facts)


def render_stroke(brush, trajectory, **options):
    """render(), with the image's placement and the stroke's facts (a Stroke)."""
    opts = _options.render_options("render", options, Error)
    image, facts = _bristle.render_stroke(_brush("render", brush),
                                          _trajectory("render", trajectory), opts)
    return Stroke(image=image, **facts)


def render(brush, trajectory, **options):
    """One stroke on a canvas sized to all the brush can reach plus 5 mm:
    the pixels of `bristle render --brush B --trajectory T` with the same
    options, as an (H, W, 3) uint8 array. Options as `bristle render`'s, by
    the names of docs/python.md ("Options"): paint="ultramarine",
    px_per_mm=8, solver="ipopt", max_step_mm=0.25, ...; threads (0, 1, 2)
    is how many threads this stroke uses (the same pixels on any count)."""
    return render_stroke(brush, trajectory, **options).image


def render_many(brushes, trajectories, threads=2, details=False, **options):
    """Many strokes, `threads` at a time (each on one thread, with its own
    OSMesa context), the GIL released: the same pixels as render() of each.
    brushes: one Brush for all, or one per trajectory. Returns a list of
    images, or of Stroke with details=True. The first failing stroke's Error
    is raised, its index in the message, once every thread has stopped."""
    where = "render_many"
    trajs = list(trajectories)
    one = isinstance(brushes, Brush)
    brush_list = [brushes] if one else list(brushes)
    if not one and len(brush_list) != len(trajs):
        raise Error(f"{where}: brushes: {len(brush_list)} brushes for {len(trajs)} "
                    "trajectories: give one brush, or one per trajectory", 64)
    if isinstance(threads, bool) or not isinstance(threads, int) or not 1 <= threads <= 64:
        raise Error(f"{where}: threads={threads!r}: must be a whole number in [1, 64]", 64)
    if "threads" in options:
        raise Error(f"{where}: each stroke takes one thread; give threads= once", 64)
    opts = _options.render_options(where, options, Error)
    opts.threads = 1
    brush_list = [_brush(where, b) for b in brush_list]
    trajs = [_trajectory(where, t) for t in trajs]
    results = _bristle.render_many(brush_list, trajs, opts, threads)
    if details:
        return [Stroke(image=image, **facts) for image, facts in results]
    return [image for image, _ in results]


def preset_options(name):
    """The options a preset (the preset= option: "default", "thumbnail")
    sets, as a dict: max_step_mm, min_rate_hz, steady_step_mm, ipopt_options."""
    o = _options.preset("preset_options", name, Error)
    return {k: getattr(o, k)
            for k in ("max_step_mm", "min_rate_hz", "steady_step_mm", "ipopt_options")}


def save_png(path, image):
    """An (H, W, C) uint8 array (C = 1 to 4) written as a PNG with bristle's
    provenance text, atomically (a failed write leaves no file)."""
    a = _np.asarray(image)
    if a.dtype != _np.uint8 or a.ndim != 3 or not 1 <= a.shape[2] <= 4 or 0 in a.shape:
        raise Error(f"save_png: image: dtype {a.dtype}, shape {a.shape}: "
                    "must be uint8 (H, W, C) with C from 1 to 4", 64)
    if not isinstance(path, (str, _os.PathLike)):
        raise Error("save_png: path: must be a str or os.PathLike", 64)
    _bristle.write_png(_os.fspath(path), _np.ascontiguousarray(a))


from ._canvas import Canvas  # noqa: E402,F401
from ._simulation import Simulation, State  # noqa: E402,F401

__all__ = ["Brush", "Canvas", "Error", "Painting", "RecordingWarning", "Simulation", "State",
           "Stroke", "Trajectory", "render_scene",
           "preset_options", "render", "render_many", "render_stroke", "save_png",
           "set_brush_library_dirs"]
