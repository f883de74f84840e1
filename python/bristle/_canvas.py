"""bristle.Canvas: strokes accumulated on one canvas (bristle/render.h, Canvas)."""
import numbers
import os

from . import Error, _brush, _bristle, _options, _trajectory

_PAPER = ("paper_colour", "paper_tooth_mm", "paper_scale_mm", "paper_seed", "mix")
_STROKE = ("preset", "paint", "load", "amount", "tip_length", "solver", "solver_max_iterations",
           "max_step_mm", "steady_step_mm", "min_rate_hz", "contact_band_mm", "threads")


def _pair(where, name, value):
    ok = (isinstance(value, (tuple, list)) and len(value) == 2 and
          all(isinstance(v, numbers.Real) and not isinstance(v, bool) for v in value))
    if not ok:
        raise Error(f"{where}: {name}: must be two numbers (x, y) in mm", 64)
    return float(value[0]), float(value[1])


class Canvas:
    """A canvas strokes are painted onto in turn, wet into wet until dry()
    (docs/paint.md). size_mm (width, height) from origin_mm (its lower-left
    corner in canvas mm) at px_per_mm; paper options as render()'s
    (paper_colour, paper_tooth_mm, paper_scale_mm, paper_seed, mix).
    One thread at a time: a stroke from a second thread waits for the first."""

    def __init__(self, size_mm, px_per_mm=8, origin_mm=(0.0, 0.0), **paper):
        where = "Canvas"
        width_mm, height_mm = _pair(where, "size_mm", size_mm)
        x0, y0 = _pair(where, "origin_mm", origin_mm)
        opts = _options.render_options(where, dict(paper, px_per_mm=px_per_mm), Error,
                                       _PAPER + ("px_per_mm",))
        # The engine checks the pixel counts (1 to 16384 a side, 64 Mpx).
        w, h = round(width_mm * opts.px_per_mm), round(height_mm * opts.px_per_mm)
        self._c = _bristle.Canvas(x0, y0, int(w), int(h), opts)
        self.px_per_mm = opts.px_per_mm
        self.origin_mm = (x0, y0)
        self.width_px, self.height_px = int(w), int(h)

    def stroke(self, brush, trajectory, **options):
        """Paints one stroke (options as render()'s preset, paint, load, amount,
        tip_length, solver and step options; the canvas keeps its paper and
        px_per_mm). Returns touched, paint_laid_mm3, failed_spine_solves."""
        where = "Canvas.stroke"
        opts = _options.render_options(where, options, Error, _STROKE)
        facts = self._c.add_stroke(_brush(where, brush), _trajectory(where, trajectory), opts)
        from . import Stroke
        return Stroke(**facts)

    def dry(self):
        """The wet paint becomes the dry layer under later strokes."""
        self._c.dry()

    def image(self, impasto=False):
        """The canvas as (height_px, width_px, 3) uint8 sRGB, row 0 at the top."""
        return self._c.image(bool(impasto))[0]

    def save(self, path, impasto=False):
        """The canvas as a PNG file, written atomically."""
        if not isinstance(path, (str, os.PathLike)):
            raise Error("Canvas.save: path: must be a str or os.PathLike", 64)
        self._c.save(os.fspath(path), bool(impasto))

    def __repr__(self):
        return (f"bristle.Canvas({self.width_px} x {self.height_px} px at "
                f"{self.px_per_mm:g} px/mm from {self.origin_mm} mm)")
