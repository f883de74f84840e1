#!/usr/bin/env python3
"""A stroke sheet drawn with matplotlib: each library brush (rows) pulled at
three press depths (columns), rendered with bristle and laid out with axes
in millimetres (docs/python.md, "Examples").

    python3 stroke_sheet.py [-o sheet.png] [--quick]

--quick: two brushes at 2 px/mm (the ctest run); otherwise four at 6 px/mm.
"""
import argparse

import matplotlib

matplotlib.use("Agg")  # no display: write the file
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import bristle  # noqa: E402


def pull(depth_mm, length_mm=20.0, n=9):
    """Press depth_mm past first contact along a gentle arc, lifting at both ends."""
    t = np.linspace(0.0, 0.6, n)
    x = np.linspace(0.0, length_mm, n)
    y = 2.0 * np.sin(np.linspace(0.0, np.pi, n))
    depth = np.full(n, depth_mm)
    depth[0] = depth[-1] = -1.0
    return bristle.Trajectory(t, np.stack([x, y], axis=1), depth_mm=depth)


def ink_box_mm(s):
    """The bounding box (x0, x1, y0, y1) in canvas mm of a stroke's paint."""
    ink = (s.image[0, 0].astype(int) - s.image.astype(int)).sum(axis=2) > 30
    rows, cols = np.nonzero(ink)
    if rows.size == 0:
        return None
    h = s.image.shape[0]
    return (s.x0_mm + cols.min() / s.px_per_mm, s.x0_mm + (cols.max() + 1) / s.px_per_mm,
            s.y0_mm + (h - rows.max() - 1) / s.px_per_mm, s.y0_mm + (h - rows.min()) / s.px_per_mm)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("-o", "--output", default="stroke_sheet.png")
    p.add_argument("--quick", action="store_true", help="two brushes at 2 px/mm")
    a = p.parse_args()
    names = ["round", "flat"] if a.quick else ["round", "flat", "filbert", "fan"]
    depths = [1.0, 3.0, 5.0]
    px_per_mm = 2 if a.quick else 6
    brushes = [bristle.Brush(n) for n in names]
    trajs = [pull(d) for _ in names for d in depths]
    strokes = bristle.render_many([b for b in brushes for _ in depths], trajs, threads=2,
                                  details=True, px_per_mm=px_per_mm, paint="burnt-umber")
    fig, axes = plt.subplots(len(names), len(depths), squeeze=False,
                             figsize=(3 * len(depths), 1.1 * len(names) + 0.6))
    for k, s in enumerate(strokes):
        ax = axes[k // len(depths)][k % len(depths)]
        h, w, _ = s.image.shape
        # The image's extent on the canvas in mm: x0, y0 is its lower-left corner.
        extent = [s.x0_mm, s.x0_mm + w / s.px_per_mm, s.y0_mm, s.y0_mm + h / s.px_per_mm]
        ax.imshow(s.image, extent=extent, interpolation="nearest")
        ax.set_title(f"{names[k // len(depths)]}, {depths[k % len(depths)]:g} mm press", fontsize=9)
        ax.tick_params(labelsize=7)
    boxes = [b for b in map(ink_box_mm, strokes) if b is not None]
    if boxes:  # every panel shows the same window round all the paint, 2 mm more
        x0, x1 = min(b[0] for b in boxes) - 2, max(b[1] for b in boxes) + 2
        y0, y1 = min(b[2] for b in boxes) - 2, max(b[3] for b in boxes) + 2
        for ax in axes.flat:
            ax.set_xlim(x0, x1)
            ax.set_ylim(y0, y1)
    fig.supxlabel("x (mm)")
    fig.supylabel("y (mm)")
    fig.tight_layout()
    fig.savefig(a.output, dpi=100)
    print(f"stroke_sheet: {len(strokes)} strokes -> {a.output}")


if __name__ == "__main__":
    main()
