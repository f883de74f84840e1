#!/usr/bin/env python3
"""Regenerates the demo trajectories in this folder (bristle-trajectory/1 CSV).

The handle position is the centre of the ferrule mouth in canvas millimetres;
the quaternion tilts the handle so that the hairs trail behind the motion, the
way a painter pulls a brush.

Each stroke is written twice. The files here give the ferrule's height z_mm, as
it suits the 20 mm round; tests and golden images rely on them. The files in
depth/ make the same motion with depth_mm in place of z_mm: how far the brush
is pressed past the height where it first touches the paper (negative: held
that far above it), which bristle works out for whatever brush paints the
stroke and the handle's tilt at each sample (docs/formats.md, "Heights relative
to the paper"). One such file suits every brush of the library, with no lift
per brush; the library sheet and the demo use them.

Run from anywhere: python3 generate.py
"""
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))
RATE_HZ = 100


def smoothstep(a):
    a = min(max(a, 0.0), 1.0)
    return a * a * (3 - 2 * a)


def trail_quaternion(dx, dy, tilt_rad):
    """Handle leaning towards the travel direction (dx, dy), hairs trailing."""
    n = math.hypot(dx, dy)
    if n < 1e-12 or tilt_rad == 0:
        return (1.0, 0.0, 0.0, 0.0)
    dx, dy = dx / n, dy / n
    # Rotating -z by tilt about axis a = z x d moves the hair direction towards -d.
    ax, ay = -dy, dx
    s = math.sin(tilt_rad / 2)
    return (math.cos(tilt_rad / 2), ax * s, ay * s, 0.0)


# Press depths past first contact (mm) of the depth/ files: those the round
# presses on the files with z_mm (6.7 mm on the straight pull, 3.7 to 9.7 on the
# S-curve, 8.4 on the press-lift), rounded; on the tilted drag 5 (the round's
# 3 left the badger's side, which touches first at 45 degrees, a thin line).
# At the deepest, the S-curve's 9.5, the 11 mm bright's ferrule stays 2.9 mm
# off the paper.
HOVER_MM = -4.0  # before and after the stroke: 4 mm above first contact


def write(name, comment, rows, height="z_mm"):
    path = os.path.join(HERE, name)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write("# bristle-trajectory/1\n")
        for line in comment:
            f.write("# " + line + "\n")
        f.write(f"t_s,x_mm,y_mm,{height},qw,qx,qy,qz\n")
        for r in rows:
            f.write(",".join(f"{v:.6f}" for v in r) + "\n")


def write_depth(name, comment, rows):
    """rows as write()'s, with the press depth in place of z."""
    write(os.path.join("depth", name), comment + [
        "depth_mm: press depth past the brush's first contact (negative: above it)."],
        rows, height="depth_mm")


def straight_pull():
    rows, depth_rows = [], []
    tilt = math.radians(20)
    q = trail_quaternion(1, 0, tilt)
    duration = 2.2
    for i in range(int(duration * RATE_HZ) + 1):
        t = i / RATE_HZ
        # 0-0.4 s: come down; 0.4-1.9 s: pull 55 mm; 1.9-2.2 s: lift.
        down = smoothstep(t / 0.4)
        lift = smoothstep((t - 1.9) / 0.3)
        x = 12 + 55 * smoothstep((t - 0.4) / 1.5)
        z = 24 - 11.5 * down + 13 * lift
        depth = HOVER_MM + (6.5 - HOVER_MM) * down - (6.5 - HOVER_MM) * lift
        rows.append((t, x, 20.0, z) + q)
        depth_rows.append((t, x, 20.0, depth) + q)
    write("straight-pull.csv",
          ["A round-brush pull: press in, pull 55 mm along +x with the handle tilted",
           "20 degrees towards the motion, lift off."], rows)
    write_depth("straight-pull.csv",
                ["A pull: press in 6.5 mm past first contact, pull 55 mm along +x with the",
                 "handle tilted 20 degrees towards the motion, lift off."], depth_rows)


def s_curve():
    rows, depth_rows = [], []
    tilt = math.radians(25)
    duration = 3.2
    for i in range(int(duration * RATE_HZ) + 1):
        t = i / RATE_HZ
        u = smoothstep((t - 0.3) / 2.6)  # progress along the S
        x = 15 + 80 * u
        y = 40 + 16 * math.sin(2 * math.pi * u)
        # Pressure: light entry, heavy in the first bend, light in the
        # middle, heavy again, then lift off at the end.
        press = 0.5 - 0.5 * math.cos(2 * math.pi * 2 * u)  # 0 -> 1 -> 0 -> 1 -> 0
        down = smoothstep(t / 0.3)
        lift = smoothstep((t - 2.9) / 0.3)
        z = 25 - 10 * down + 11 * lift - 6 * press * (1 - lift)
        # 3.5 mm in the light parts, 9.5 mm in the heavy bends.
        depth = (HOVER_MM + (3.5 - HOVER_MM) * down - (3.5 - HOVER_MM) * lift
                 + 6 * press * (1 - lift))
        # The handle leans along the path's tangent (d/du), also before and
        # after the motion, so that it never turns in place on the paper.
        q = trail_quaternion(80, 16 * 2 * math.pi * math.cos(2 * math.pi * u), tilt)
        rows.append((t, x, y, z) + q)
        depth_rows.append((t, x, y, depth) + q)
    write("s-curve.csv",
          ["An S-curve with a round brush: press in, two heavy bends and a light",
           "middle, handle tilted 25 degrees towards the motion, lift off."], rows)
    write_depth("s-curve.csv",
                ["An S-curve: press in 3.5 mm past first contact, 9.5 mm in the two bends,",
                 "handle tilted 25 degrees towards the motion, lift off."], depth_rows)


def press_lift():
    rows, depth_rows = [], []
    duration = 2.0
    for i in range(int(duration * RATE_HZ) + 1):
        t = i / RATE_HZ
        press = math.sin(math.pi * t / duration) ** 2  # 0 -> 1 -> 0
        z = 24 - 12 * press
        depth = HOVER_MM + (8 - HOVER_MM) * press
        rows.append((t, 30.0, 30.0, z, 1.0, 0.0, 0.0, 0.0))
        depth_rows.append((t, 30.0, 30.0, depth, 1.0, 0.0, 0.0, 0.0))
    write("press-lift.csv",
          ["A vertical handle pressed straight down 8 mm past first contact and lifted."],
          rows)
    write_depth("press-lift.csv",
                ["A vertical handle pressed straight down 8 mm past first contact and lifted."],
                depth_rows)


def press_hold_lift():
    """A blot with a dwell: pressed, held still, lifted (depth/ only)."""
    rows = []
    press_s, hold_s, lift_s, depth_mm = 0.3, 1.5, 0.3, 4.0
    duration = press_s + hold_s + lift_s
    for i in range(int(round(duration * RATE_HZ)) + 1):
        t = i / RATE_HZ
        if t <= press_s:
            depth = HOVER_MM + (depth_mm - HOVER_MM) * smoothstep(t / press_s)
        elif t <= press_s + hold_s:
            depth = depth_mm
        else:
            depth = depth_mm + (HOVER_MM - depth_mm) * smoothstep((t - press_s - hold_s) / lift_s)
        rows.append((t, 30.0, 30.0, depth, 1.0, 0.0, 0.0, 0.0))
    write_depth("press-hold-lift.csv",
                ["A vertical handle pressed 4 mm past first contact in 0.3 s, held exactly",
                 "still for 1.5 s (a blot soaking in; the brush comes to rest and stops",
                 "solving: docs/dynamics.md, \"A brush held still\"), lifted in 0.3 s."],
                rows)


def broadside_pull():
    rows, depth_rows = [], []
    tilt = math.radians(25)
    q = trail_quaternion(0, -1, tilt)
    duration = 2.2
    for i in range(int(duration * RATE_HZ) + 1):
        t = i / RATE_HZ
        # 0-0.4 s: come down; 0.4-1.9 s: pull 45 mm towards -y; 1.9-2.2 s: lift.
        down = smoothstep(t / 0.4)
        lift = smoothstep((t - 1.9) / 0.3)
        y = 60 - 45 * smoothstep((t - 0.4) / 1.5)
        z = 22 - 9.5 * down + 11 * lift
        depth = HOVER_MM + (5 - HOVER_MM) * down - (5 - HOVER_MM) * lift
        rows.append((t, 30.0, y, z) + q)
        depth_rows.append((t, 30.0, y, depth) + q)
    write("broadside-pull.csv",
          ["A flat brush pulled broadside: press in, pull 45 mm towards -y (across",
           "the brush's width axis x) with the handle tilted 25 degrees towards the",
           "motion, lift off. The One-Stroke motion of a double-loaded flat."], rows)
    write_depth("broadside-pull.csv",
                ["A brush pulled broadside: press in 5 mm past first contact, pull 45 mm",
                 "towards -y (across the brush's width axis x) with the handle tilted 25",
                 "degrees towards the motion, lift off."], depth_rows)


def tilted_drag():
    rows, depth_rows = [], []
    # The handle leans 45 degrees sideways (towards +y, across the motion), so
    # the belly of the brush, not its tip, drags along the paper: the side
    # stroke painters use for broad, uneven marks.
    q = trail_quaternion(0, 1, math.radians(45))
    duration = 2.2
    for i in range(int(duration * RATE_HZ) + 1):
        t = i / RATE_HZ
        # 0-0.4 s: come down; 0.4-1.9 s: drag 50 mm along +x; 1.9-2.2 s: lift.
        down = smoothstep(t / 0.4)
        lift = smoothstep((t - 1.9) / 0.3)
        x = 12 + 50 * smoothstep((t - 0.4) / 1.5)
        z = 20 - 8 * down + 9 * lift
        depth = HOVER_MM + (5 - HOVER_MM) * down - (5 - HOVER_MM) * lift
        rows.append((t, x, 30.0, z) + q)
        depth_rows.append((t, x, 30.0, depth) + q)
    write("tilted-drag.csv",
          ["A handle leaning 45 degrees across the motion (hairs towards -y),",
           "dragged 50 mm along +x on the belly of the brush, lifted."], rows)
    write_depth("tilted-drag.csv",
                ["A handle leaning 45 degrees across the motion (hairs towards -y), pressed",
                 "5 mm past first contact, dragged 50 mm along +x on the belly, lifted."],
                depth_rows)


if __name__ == "__main__":
    broadside_pull()
    straight_pull()
    s_curve()
    press_lift()
    press_hold_lift()
    tilted_drag()
