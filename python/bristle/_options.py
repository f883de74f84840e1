"""Keyword options to the engine's RenderOptions (include/bristle/render.h).

Each option keeps the name of the C++ field (and of `bristle render`'s option
of the same meaning); its value is checked for type here and for range by the
engine, so every bad value is a bristle.Error naming the option.
"""
import numbers

from . import _bristle

# name -> kind; the ranges are the engine's (docs/python.md, "Options").
# preset names a set of them (bristle/render.h, presetOptions: "default",
# "thumbnail"); an option given by name beside it still wins.
RENDER_OPTIONS = {
    "preset": "preset",
    "paint": "str",
    "load": ("solid", "across", "tip"),
    "amount": "real",
    "tip_length": "real",
    "mix": ("km", "rgb"),
    "paper_colour": "str",
    "paper_tooth_mm": "real",
    "paper_scale_mm": "real",
    "paper_seed": "seed",
    "impasto": "bool",
    "px_per_mm": "real",
    "solver": ("ipopt", "slsqp"),
    "solver_max_iterations": "int",
    "max_step_mm": "real",
    "steady_step_mm": "real",
    "min_rate_hz": "real",
    "contact_band_mm": "real",
    "ipopt_options": "strs",
    "threads": "int",
}

_ENUMS = {"load": _bristle.PaintLoad, "mix": _bristle.PaintMix, "solver": _bristle.Solver}


def _value(where, name, kind, value, error):
    if isinstance(kind, tuple):
        if value not in kind:
            raise error(f"{where}: {name}={value!r}: must be one of {', '.join(kind)}", 64)
        return getattr(_ENUMS[name], value)
    if kind == "str":
        if not isinstance(value, str):
            raise error(f"{where}: {name}: must be a str", 64)
        return value
    if kind == "strs":
        items = None if isinstance(value, (str, bytes)) else value
        if not isinstance(items, (list, tuple)) or not all(isinstance(v, str) for v in items):
            raise error(f"{where}: {name}: must be a list of str (NAME=VALUE)", 64)
        return list(items)
    if kind == "bool":
        if not isinstance(value, (bool,)):
            raise error(f"{where}: {name}: must be True or False", 64)
        return value
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise error(f"{where}: {name}: must be a real number", 64)
    if kind in ("int", "seed"):
        if int(value) != value:
            raise error(f"{where}: {name}={value!r}: must be a whole number", 64)
        limit = 2**64 - 1 if kind == "seed" else 100000
        if not 0 <= value <= limit:
            raise error(f"{where}: {name}={value!r}: must be in [0, {limit}]", 64)
        return int(value)
    return float(value)


def preset(where, value, error):
    """The _bristle.RenderOptions of the preset named `value`, or an Error."""
    if not isinstance(value, str):
        raise error(f"{where}: preset: must be a str", 64)
    try:
        return _bristle.preset_options(value)
    except error as e:
        raise error(f"{where}: {e.message}", e.exit_code) from None


def render_options(where, options, error, allowed=None):
    """A _bristle.RenderOptions from keyword options (the preset's, then each
    option given by name); unknown names are errors."""
    out = _bristle.RenderOptions()
    for name, value in options.items():
        kind = RENDER_OPTIONS.get(name)
        if kind is None or (allowed is not None and name not in allowed):
            known = ", ".join(allowed if allowed is not None else RENDER_OPTIONS)
            raise error(f"{where}: unknown option {name!r} (known: {known})", 64)
        if kind == "preset":
            out = preset(where, value, error)
    for name, value in options.items():
        if name != "preset":
            setattr(out, name, _value(where, name, RENDER_OPTIONS[name], value, error))
    return out
