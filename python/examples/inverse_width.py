#!/usr/bin/env python3
"""An inverse problem on top of render: which press-depth profile along a
straight 24 mm pull paints a given width profile? scipy.optimize searches
the depths at three stations (start, middle, end of the pull) for the
widths measured at the same stations of a target stroke (docs/python.md,
"Examples").

    python3 inverse_width.py [--evaluations 60] [--px-per-mm 3]

The target is painted by a known profile, so the answer can be checked.
The search stays where the width answers the press: at 3 px/mm the round
paints about 2 mm wide for any press of 1-3 mm (its belly not yet spread),
then 2.2-3.0 mm at 4 mm, 4.1-4.8 at 5 and 4.7-5.7 at 6. Searched over
0.5-6 mm, every depth under 3 mm painted the same, and 40 renders left an
rms width error of 0.58 mm; over 4-6.5 mm they leave 0.09 mm.
"""
import argparse

import numpy as np
from scipy.optimize import minimize

import bristle

LENGTH_MM = 24.0
STATIONS_MM = np.array([6.0, 12.0, 18.0])  # where widths are measured, along the pull
SAMPLES = 13
BAND_MM = 1.5  # half the stretch of the pull a station's width is averaged over
DEPTH_RANGE_MM = (4.0, 6.5)  # the depths searched, where the width grows with the press


def pull(depths_mm):
    """The pull with its press depth interpolated through the stations'
    depths, in the air at both ends."""
    x = np.linspace(0, LENGTH_MM, SAMPLES)
    depth = np.interp(x, STATIONS_MM, depths_mm)
    depth[0] = depth[-1] = -1.0
    t = np.linspace(0, 0.8, SAMPLES)
    return bristle.Trajectory(t, np.stack([x, np.zeros(SAMPLES)], 1), depth_mm=depth)


def widths_mm(brush, depths_mm, px_per_mm):
    """The painted width (mm) across the pull at each station: the pixels
    darker than the paper by more than 10 % of a channel, counted down each
    column and averaged over the columns within BAND_MM of the station (a
    smoother measure than one column's whole pixels)."""
    s = bristle.render_stroke(brush, pull(depths_mm), px_per_mm=px_per_mm, paint="sumi-ink")
    paper = s.image[0, 0].astype(int)
    ink = (paper - s.image.astype(int)).sum(axis=2) > 3 * 25
    per_column = ink.sum(axis=0) / px_per_mm
    x_mm = s.x0_mm + (np.arange(ink.shape[1]) + 0.5) / px_per_mm
    return np.array([per_column[np.abs(x_mm - x) <= BAND_MM].mean() for x in STATIONS_MM])


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--evaluations", type=int, default=60, help="renders the search may make")
    p.add_argument("--px-per-mm", type=float, default=3.0)
    a = p.parse_args()
    brush = bristle.Brush("round")
    truth = np.array([4.5, 5.8, 5.0])
    target = widths_mm(brush, truth, a.px_per_mm)
    print(f"inverse_width: target widths {np.round(target, 2)} mm (from depths {truth} mm)")

    def error(depths):
        # Depths outside the range are penalised, not rendered.
        if np.any(depths < DEPTH_RANGE_MM[0]) or np.any(depths > DEPTH_RANGE_MM[1]):
            return 1e3
        return float(np.sum((widths_mm(brush, depths, a.px_per_mm) - target) ** 2))

    start = np.array([5.2, 5.2, 5.2])
    r = minimize(error, start, method="Nelder-Mead",
                 options={"maxfev": a.evaluations, "xatol": 0.05, "fatol": 0.01})
    found = widths_mm(brush, r.x, a.px_per_mm)
    print(f"inverse_width: depths {np.round(r.x, 2)} mm after {r.nfev} renders paint widths "
          f"{np.round(found, 2)} mm; rms width error {np.sqrt(np.mean((found - target) ** 2)):.2f} "
          f"mm (from {np.sqrt(np.mean((widths_mm(brush, start, a.px_per_mm) - target) ** 2)):.2f})")


if __name__ == "__main__":
    main()
