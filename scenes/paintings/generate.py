#!/usr/bin/env python3
"""Regenerates the paintings in this folder: scene files (bristle-scene/1 JSON)
and the trajectories they place (bristle-trajectory/1 CSV).

  petals.json       One-Stroke flower wreath: double-loaded flat, petals + leaves
  calligraphy.json  the character 永 ("eternity", the eight principles of Yong)
                    in its five strokes with a calligraphy brush and ink
  landscape.json    clouds (filbert, badger), horizon (flat), dry-brush grass (fan)

A stroke is written as key points (x, y, depth, yaw) joined by a Catmull-Rom
spline and timed by its length at the stroke's speed. depth is how far the
handle is pushed below the height where the hair tips first touch the paper
(negative: in the air). Many strokes share one trajectory written around (0, 0)
and placed by the scene (rotate_deg about (0, 0), then offset_mm).

Python 3 standard library only. Run from anywhere: python3 generate.py
"""
import json
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))
RATE_HZ = 100        # trajectory samples per second
HOVER_MM = 2.5       # strokes start and end with the tips this far above the paper
DESCEND_MM_S = 40.0  # how fast the handle comes down or lifts where it hardly moves

# Hair length (mm) of the library's brushes (scenes/brushes/*.json).
HAIR_MM = {"flat": 16.0, "round": 20.0, "calligraphy": 30.0, "fan": 22.0,
           "filbert": 15.0, "badger": 25.0}


# --- quaternions (w, x, y, z) ---------------------------------------------

def qmul(a, b):
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return (aw * bw - ax * bx - ay * by - az * bz,
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw)


def yaw(deg):
    """Turn about the handle axis: the brush's x (its width axis) to angle deg."""
    h = math.radians(deg) / 2
    return (math.cos(h), 0.0, 0.0, math.sin(h))


def lean(dx, dy, tilt_deg):
    """Handle tilted towards the travel direction (dx, dy): the hairs trail."""
    n = math.hypot(dx, dy)
    if n < 1e-12 or tilt_deg == 0:
        return (1.0, 0.0, 0.0, 0.0)
    dx, dy = dx / n, dy / n
    # Rotating -z about a = z x d moves the hair direction towards -d.
    s = math.sin(math.radians(tilt_deg) / 2)
    return (math.cos(math.radians(tilt_deg) / 2), -dy * s, dx * s, 0.0)


# --- strokes ----------------------------------------------------------------

def catmull_rom(p0, p1, p2, p3, u):
    u2, u3 = u * u, u * u * u
    return tuple(0.5 * (2 * b + (-a + c) * u + (2 * a - 5 * b + 4 * c - d) * u2 +
                        (-a + 3 * b - 3 * c + d) * u3)
                 for a, b, c, d in zip(p0, p1, p2, p3))


def stroke(keys, speed_mm_s, brush, tilt_deg=0.0, hover=True, lean_deg=None):
    """Samples a stroke through key points (x, y, depth_mm, yaw_deg).

    The handle leans tilt_deg towards the travel direction, or towards the
    fixed direction lean_deg (degrees from +x) when given: a handle that keeps
    its lean while the hairs touch is what a painter does in a loop or a wave,
    and it spares the simulation a brush turning on the paper. With hover, the brush comes down onto the first key from HOVER_MM above
    and lifts off after the last. Returns rows (t, x, y, z, qw, qx, qy, qz).
    """
    keys = [tuple(float(v) for v in k) for k in keys]
    if hover:
        keys = [keys[0][:2] + (-HOVER_MM,) + keys[0][3:]] + keys + \
               [keys[-1][:2] + (-HOVER_MM,) + keys[-1][3:]]
    # Duration of each segment: its length at the speed, or the vertical
    # travel at the descent speed, whichever is longer.
    durations = []
    for a, b in zip(keys, keys[1:]):
        d_xy = math.hypot(b[0] - a[0], b[1] - a[1])
        durations.append(max(d_xy / speed_mm_s, abs(b[2] - a[2]) / DESCEND_MM_S, 0.02))
    ext = [keys[0]] + keys + [keys[-1]]
    total = sum(durations)
    contact_z = HAIR_MM[brush] * math.cos(math.radians(tilt_deg))
    samples = []
    n = int(math.ceil(total * RATE_HZ))
    for i in range(n + 1):
        t = min(i / RATE_HZ, total)
        k, acc = 0, 0.0
        while k < len(durations) - 1 and acc + durations[k] < t:
            acc += durations[k]
            k += 1
        u = min(max((t - acc) / durations[k], 0.0), 1.0)
        samples.append((t,) + catmull_rom(ext[k], ext[k + 1], ext[k + 2], ext[k + 3], u))
    rows = []
    for i, (t, x, y, depth, yaw_deg) in enumerate(samples):
        # Travel direction from the neighbours (the next motion while still).
        dx = dy = 0.0
        for j in list(range(i + 1, len(samples))) + list(range(i - 1, -1, -1)):
            dx, dy = samples[j][1] - x, samples[j][2] - y
            if j < i:
                dx, dy = -dx, -dy
            if math.hypot(dx, dy) > 1e-4:
                break
        if lean_deg is not None:
            dx, dy = math.cos(math.radians(lean_deg)), math.sin(math.radians(lean_deg))
        q = qmul(lean(dx, dy, tilt_deg), yaw(yaw_deg))
        rows.append((t, x, y, contact_z - depth) + q)
    return rows


def write_trajectory(rel, comment, rows):
    path = os.path.join(HERE, rel)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write("# bristle-trajectory/1\n")
        for line in comment:
            f.write("# " + line + "\n")
        f.write("t_s,x_mm,y_mm,z_mm,qw,qx,qy,qz\n")
        for r in rows:
            f.write(",".join(f"{v:.5f}" for v in r) + "\n")
    return rel


def placed(brush, trajectory, paint, offset=(0, 0), rotate=0.0, dry_before=False):
    s = {"brush": "../brushes/" + brush + ".json", "trajectory": trajectory, "paint": paint}
    if offset != (0, 0) or rotate:
        s["placement"] = {"offset_mm": [round(offset[0], 3), round(offset[1], 3)],
                          "rotate_deg": round(rotate, 3)}
    if dry_before:
        s["dry_before"] = True
    return s


def write_scene(name, scene):
    with open(os.path.join(HERE, name), "w") as f:
        json.dump(scene, f, indent=1, ensure_ascii=False)
        f.write("\n")


# --- 1. One-Stroke petals -----------------------------------------------------

def petal_keys(sweep_deg, ruffles, reach, trail_mm):
    """A One-Stroke petal around the flower centre (0, 0), pointing along +x.

    The double-loaded flat stands with its width along the radius (paints[1],
    the +x end of the brush, outside) and sweeps across the petal, pressed,
    wiggling in and out to ruffle the outer edge; then it slides back to the
    centre on its chisel and lifts. The handle leans towards +x all along;
    the pressed hairs trail about trail_mm behind it (towards -x), so the
    handle runs that much further out than the paint lands.
    """
    keys = []
    n = 14
    for i in range(n + 1):
        u = i / n
        phi = -sweep_deg / 2 + sweep_deg * u
        r = reach + 0.9 * math.sin(ruffles * math.pi * u) * math.sin(math.pi * u)
        depth = 3.5 + 1.5 * math.sin(math.pi * u)
        a = math.radians(phi)
        keys.append((r * math.cos(a) + trail_mm, r * math.sin(a), depth, phi))
    a = math.radians(sweep_deg / 2 + 8)
    keys.append((0.55 * reach * math.cos(a) + trail_mm, 0.55 * reach * math.sin(a), 1.0,
                 sweep_deg / 2 + 25))
    return keys


def leaf_half_keys(side, length):
    """Half a One-Stroke leaf from the base (0, 0) to the tip (length, 0):
    pressed broadside at the base, sliding out along the midrib while the
    brush turns onto its chisel and lifts to the point. side = +1 upper half,
    -1 lower half."""
    keys = []
    n = 10
    for i in range(n + 1):
        u = i / n
        x = length * u
        y = side * 2.6 * math.sin(math.pi * (0.12 + 0.88 * u)) * (1 - 0.35 * u)
        depth = 2.6 * (1 - u) ** 0.7 + 0.3
        turn = 90 - side * 65 * u
        keys.append((x, y, depth, turn))
    return keys


def vine_keys(radius, start_deg, span_deg):
    """A thin vine along a circle about (0, 0): the flat pulled on its chisel."""
    keys = []
    n = 8
    for i in range(n + 1):
        a = math.radians(start_deg + span_deg * i / n)
        depth = 1.2 + 0.6 * math.sin(math.pi * i / n)
        # Width axis along the travel (the tangent): the chisel edge leads.
        keys.append((radius * math.cos(a), radius * math.sin(a), depth,
                     start_deg + span_deg * i / n + 90))
    return keys


def petals():
    d = "petals/"
    t_petal_a = write_trajectory(d + "petal-a.csv", [
        "One-Stroke petal about (0, 0), pointing along +x: a flat sweeps 70 degrees",
        "with its width along the radius, ruffling the outer edge, then slides back",
        "to the centre on its chisel."], stroke(petal_keys(70, 3, 8.0, 8.5), 22, "flat", tilt_deg=12, lean_deg=0))
    t_petal_b = write_trajectory(d + "petal-b.csv", [
        "As petal-a with two ruffles and a slightly longer reach."],
        stroke(petal_keys(74, 2, 8.6, 8.5), 22, "flat", tilt_deg=12, lean_deg=0))
    t_leaf_up = write_trajectory(d + "leaf-upper.csv", [
        "Upper half of a One-Stroke leaf from (0, 0) to (22, 0): press, slide and",
        "turn onto the chisel, lift to the point."],
        stroke(leaf_half_keys(+1, 22), 28, "flat", tilt_deg=15, lean_deg=0))
    t_leaf_lo = write_trajectory(d + "leaf-lower.csv", [
        "Lower half of the leaf, the mirror image of leaf-upper."],
        stroke(leaf_half_keys(-1, 22), 28, "flat", tilt_deg=15, lean_deg=0))
    ring = 34.0
    t_vine = write_trajectory(d + "vine.csv", [
        "A 70 degree arc of radius 34 mm about (0, 0), the flat on its chisel edge."],
        stroke(vine_keys(ring, 0, 70), 45, "flat", tilt_deg=12, lean_deg=125))
    t_dot = write_trajectory(d + "dot.csv", [
        "A round brush dabbed down and lifted at (0, 0): the flower's centre."],
        stroke([(0, 0, 0.5, 0), (0.4, 0.2, 2.5, 0), (0.2, 0.5, 2.5, 0), (0, 0.2, 1.0, 0)],
               10, "round", tilt_deg=12, lean_deg=45))

    cx, cy = 60.0, 58.0
    # Two thirds red at the centre side, white at the rim.
    red_white = {"mode": "across", "paints": ["cadmium-red", "cadmium-red", "titanium-white"],
                 "amount": 1.0}
    green_yellow = {"mode": "across", "paints": ["viridian", "cadmium-yellow"], "amount": 0.9}
    yellow_green = {"mode": "across", "paints": ["cadmium-yellow", "viridian"], "amount": 0.9}
    vine_paint = {"paints": ["viridian"], "amount": 0.6}
    strokes = []
    # The vine ring, in arcs that leave gaps under the flowers.
    flowers = [45, 165, 285]
    for f in flowers:
        strokes.append(placed("flat", t_vine, vine_paint, (cx, cy), f + 25))
    # Two leaves on the ring between each pair of flowers, pointing outwards
    # and inwards alternately, each of two halves.
    for f in flowers:
        for k, (along, out) in enumerate([(50, 35), (85, -40)]):
            a = math.radians(f + along)
            base = (cx + ring * math.cos(a), cy + ring * math.sin(a))
            rot = f + along + out
            strokes.append(placed("flat", t_leaf_up, yellow_green, base, rot))
            strokes.append(placed("flat", t_leaf_lo, green_yellow, base, rot))
    # Five petals per flower, then its yellow centre.
    for n, f in enumerate(flowers):
        a = math.radians(f)
        centre = (cx + ring * math.cos(a), cy + ring * math.sin(a))
        for p in range(5):
            strokes.append(placed("flat", t_petal_a if p % 2 == 0 else t_petal_b, red_white,
                                  centre, f + 18 * n + 72 * p, dry_before=(n == 0 and p == 0)))
        strokes.append(placed("round", t_dot, {"paints": ["cadmium-yellow"], "amount": 0.8},
                              centre))
    write_scene("petals.json", {
        "format": "bristle-scene/1",
        "name": "One-Stroke wreath",
        "description": "Three five-petal flowers on a vine ring with leaves, painted "
                       "One-Stroke style: each petal and each half leaf one stroke of a "
                       "double-loaded flat (paper Fig. 1).",
        "canvas": {"size_mm": [120, 116], "px_per_mm": 6, "background": "#f4efe2",
                   "paper": {"tooth_depth_mm": 0.02, "tooth_scale_mm": 0.35, "seed": 7}},
        "sim": {"rate_hz": 100, "max_step_mm": 0.3},
        "mix": "km",
        "solver": "slsqp",
        "strokes": strokes,
    })


# --- 2. calligraphy: 永 ---------------------------------------------------------

# The five strokes of 永 in their order, in a 100-unit box (y up), as key
# points (x, y, depth_mm). Each begins with a press (the entry), is pulled with
# the pressure the stroke's shape asks for, and ends lifting (a point) or
# pressing (a blunt end). Depths are for the calligraphy brush held upright.
# A stroke enters as a calligrapher's exposed tip (露锋) does: the brush comes
# down while already travelling the stroke's way, from ENTRY_APPROACH_MM back
# along its first segment, and presses to about the body's depth, so that the
# hair trails before the press builds (docs/fidelity.md, "Entries and
# blots"). Pressed deeper than the body while barely moving, the brush
# leaves a bead of a head about twice the body's width.
#
# The pressed belly prints behind the handle (its footprint trails it by
# 5-8 mm at these presses, docs/fidelity.md "Real brushes"), so a press
# shows where the hair lies, not where the handle is:
# - the dot enters light (0.5 mm) and fast and presses only at its end, where
#   the handle slows into the press (顿) and turns back up as it lifts (回锋),
#   so that its weight gathers at the blunt lower end;
# - the turns of 横折钩 and 横撇 are square: the horizontal keeps its body's
#   depth to the corner, the brush lifts there (off the paper before the
#   long vertical, so that the hair trailing left along the horizontal does
#   not bow the vertical's top) and presses again down the next stroke's
#   way; a press while the handle slows along the horizontal left a lump;
# - 撇 comes down along its own line and presses to its body's depth over
#   its first 4 mm, and the horizontals press to theirs over their first
#   3 mm: pressed over 1.6 mm, nearly standing, they began with round knobs.
ENTRY_APPROACH_MM = 8.0
YONG = [
    ("dot", "点 dot: enters light, pressed at its end, turns back as it lifts: blunt end",
     [(45, 93, 0.5), (49, 89, 1.5), (52, 86, 3.0), (54, 84, 5.0), (54.5, 83.5, 6.0),
      (53.5, 84.5, 3.0), (52.5, 85.5, 0.5)]),
    ("heng-zhe-gou", "横折钩 horizontal, square turn (lifted to the point, pressed down and "
     "right into the shoulder), long vertical, hook to the left",
     [(29, 73, 0.5), (31, 73.6, 1.4), (34, 74.3, 2.6), (40, 74.6, 3.0), (50, 75.3, 3.0),
      (55, 76, 3.0), (56.5, 76.2, 0.3), (58.4, 75.2, 3.8), (57.9, 72, 4.4), (57.5, 68, 4.6),
      (57, 60, 4.8), (56.5, 40, 4.8), (56.5, 22, 4.8), (56.5, 13, 5.5), (55, 12, 4.0),
      (49, 17, 1.8), (46, 20, 0.3)]),
    ("heng-pie", "横撇 short horizontal, square turn, sweep down to the left, tapering",
     [(17, 56, 0.5), (19, 56.6, 1.3), (22, 57.2, 2.5), (28, 57.4, 2.8), (34, 58, 2.8),
      (37, 58.4, 1.8), (38, 57, 3.8), (36, 52, 3.6), (28, 44, 3.2), (20, 35, 2.2),
      (12, 28, 0.8), (9, 26, 0.1)]),
    ("pie", "撇 short left-falling stroke from the upper right, tapering",
     [(85, 67, 1.5), (81, 62.5, 3.0), (76, 57.5, 3.2), (70, 52, 2.5), (63, 47, 1.0),
      (60, 45.5, 0.2)]),
    ("na", "捺 right-falling stroke, growing heavier, pressed flat, then drawn out",
     [(61, 47, 0.8), (65, 42, 1.8), (71, 34, 2.8), (77, 26, 4.0), (82, 20, 5.5),
      (86, 17.5, 5.0), (92, 15.5, 2.5), (98, 14.5, 0.5)]),
]


def calligraphy():
    scale = 0.8  # 100 units -> 80 mm
    ox, oy = 8.0, 6.0
    strokes = []
    for i, (name, comment, pts) in enumerate(YONG):
        keys = [(ox + x * scale, oy + y * scale, depth, 0.0) for x, y, depth in pts]
        (x0, y0, _, _), (x1, y1, _, _) = keys[:2]
        run = math.hypot(x1 - x0, y1 - y0)
        approach = (x0 - (x1 - x0) / run * ENTRY_APPROACH_MM,
                    y0 - (y1 - y0) / run * ENTRY_APPROACH_MM, -HOVER_MM, 0.0)
        keys = [approach] + keys + [keys[-1][:2] + (-HOVER_MM, 0.0)]
        rel = write_trajectory("calligraphy/%d-%s.csv" % (i + 1, name), [
            "Stroke %d of the character 永: %s." % (i + 1, comment),
            "The calligraphy brush held upright, pressure modulated by height."],
            stroke(keys, 30, "calligraphy", tilt_deg=0, hover=False))
        strokes.append(placed("calligraphy", rel, {"paints": ["sumi-ink"], "amount": 1.0}))
    write_scene("calligraphy.json", {
        "format": "bristle-scene/1",
        "name": "永 (eternity)",
        "description": "The character 永 in its five strokes and their order, with a "
                       "calligraphy brush and ink: press, pull, lift.",
        "canvas": {"size_mm": [96, 96], "px_per_mm": 6, "background": "#f3ecdc",
                   "paper": {"tooth_depth_mm": 0.03, "tooth_scale_mm": 0.3, "seed": 3}},
        "sim": {"rate_hz": 100, "max_step_mm": 0.3},
        "mix": "km",
        # Ipopt, the reference: the calligraphy brush's spines push on each
        # other through hair volume, which Ipopt solves as one problem
        # (docs/dynamics.md, "Hair volume"), as its goldens and tests do.
        "solver": "ipopt",
        "strokes": strokes,
    })


# --- 3. landscape sketch ----------------------------------------------------------

def puff_keys(radius, turns):
    """A cloud puff about (0, 0): small scumbling loops that drift right."""
    keys = []
    n = int(10 * turns)
    for i in range(n + 1):
        u = i / n
        a = 2 * math.pi * turns * u + math.pi
        r = radius * (0.55 + 0.45 * math.sin(math.pi * u))
        keys.append((r * math.cos(a) + 3 * u, 0.7 * r * math.sin(a),
                     2.5 + 1.5 * math.sin(math.pi * u), math.degrees(a)))
    return keys


def grass_keys(height, bend):
    """A dry-brush grass flick from (0, 0) upwards: the fan touches down and
    flicks up and a little sideways while lifting."""
    return [(0, 0, 9.0, 0), (0.05 * bend, 0.08 * height, 11.0, 0), (0.2 * bend, 0.3 * height, 10.0, 0),
            (0.6 * bend, 0.65 * height, 6.0, 0), (bend, height, -0.5, 0)]


def landscape():
    d = "landscape/"
    t_puff = write_trajectory(d + "cloud-puff.csv", [
        "A cloud puff about (0, 0): a filbert scumbled in loops."],
        stroke(puff_keys(5.0, 1.5), 30, "filbert", tilt_deg=10, lean_deg=0))
    t_cloud_base = write_trajectory(d + "cloud-base.csv", [
        "A cloud's underside softened: a badger swept 34 mm along +x."],
        stroke([(0, 0, 1.5, 0), (10, -0.8, 3.0, 0), (22, -0.5, 3.0, 0), (34, 0.5, 1.0, 0)], 45,
               "badger", tilt_deg=15, lean_deg=0))
    hills = [(2, 46), (20, 50), (38, 47), (58, 52), (78, 48), (98, 45), (120, 49), (140, 47),
             (158, 46)]
    t_hills = write_trajectory(d + "hills.csv", [
        "Distant hills on the horizon: the flat pulled broadside across the canvas,",
        "rising and falling."],
        stroke([(x, y, 3.0 + 0.8 * math.sin(i), 90) for i, (x, y) in enumerate(hills)], 60,
               "flat", tilt_deg=15, lean_deg=0))
    t_field = write_trajectory(d + "field.csv", [
        "A band of field below the horizon: the flat broadside, 150 mm along +x."],
        stroke([(0, 0, 3.5, 90), (40, 0.8, 4.0, 90), (80, -0.5, 3.5, 90), (120, 0.6, 4.0, 90),
                (150, 0, 3.0, 90)], 70, "flat", tilt_deg=15, lean_deg=0))
    t_grass_l = write_trajectory(d + "grass-left.csv", [
        "A grass flick from (0, 0) up and to the left with the fan brush."],
        stroke(grass_keys(16, -4), 25, "fan", tilt_deg=15, lean_deg=90))
    t_grass_r = write_trajectory(d + "grass-right.csv", [
        "A grass flick from (0, 0) up and to the right with the fan brush."],
        stroke(grass_keys(13, 5), 25, "fan", tilt_deg=15, lean_deg=90))

    strokes = []
    sky_grey = "#8e9bb3"
    cloud = {"mode": "across", "paints": [sky_grey, "titanium-white"], "amount": 0.8}
    for cx, cy, puffs in [(38, 82, 3), (108, 86, 4)]:
        for k in range(puffs):
            strokes.append(placed("filbert", t_puff, cloud,
                                  (cx + 7 * k - 3.5 * puffs, cy + 3 * math.sin(2.1 * k)),
                                  rotate=8 * math.sin(k)))
        # The badger, nearly clean, swept through the puffs' wet undersides:
        # it lifts the paint where it lies thick and lays it down thin beyond,
        # softening the cloud into the sky (docs/fidelity.md, "The badger softener").
        strokes.append(placed("badger", t_cloud_base,
                              {"paints": ["titanium-white"], "amount": 0.25},
                              (cx - 3.5 * puffs + 2, cy - 4)))
    strokes.append(placed("flat", t_hills,
                          {"mode": "across", "paints": ["ultramarine", "#a6a8c4"], "amount": 0.8},
                          dry_before=True))
    strokes.append(placed("flat", t_field,
                          {"mode": "across", "paints": ["viridian", "yellow-ochre"], "amount": 0.9},
                          (5, 38)))
    strokes.append(placed("flat", t_field,
                          {"mode": "across", "paints": ["yellow-ochre", "burnt-sienna"], "amount": 0.7},
                          (5, 31)))
    # Dry-brush grass: little paint on the fan, flicked up in clumps.
    # Opaque paints: a glaze this thin would hardly show.
    grass = [{"paints": ["#3d5f27"], "amount": 1.0},
             {"paints": ["yellow-ochre"], "amount": 1.0},
             {"paints": ["burnt-sienna"], "amount": 1.0}]
    k = 0
    for clump_x in [14, 45, 80, 115, 146]:
        for j in range(3):
            x = clump_x + 6 * j - 9 + 2 * math.sin(3.7 * k)
            y = 17 + 4 * math.sin(1.3 * k) ** 2
            strokes.append(placed("fan", t_grass_l if (j + k) % 2 else t_grass_r, grass[k % 3],
                                  (x, y), rotate=10 * math.sin(2.3 * k), dry_before=(k == 0)))
            k += 1
    write_scene("landscape.json", {
        "format": "bristle-scene/1",
        "name": "landscape sketch",
        "description": "Clouds scumbled with a filbert and softened with a badger, hills and "
                       "fields with the flat, dry-brush grass flicked up with the fan "
                       "(paper Fig. 11).",
        "canvas": {"size_mm": [160, 100], "px_per_mm": 6, "background": "#f2eee3",
                   "paper": {"tooth_depth_mm": 0.01, "tooth_scale_mm": 0.5, "seed": 11}},
        "sim": {"rate_hz": 100, "max_step_mm": 0.3},
        "mix": "km",
        "solver": "slsqp",
        "strokes": strokes,
    })


if __name__ == "__main__":
    petals()
    calligraphy()
    landscape()
