#!/usr/bin/env python3
"""Writes pointer-events.csv: a SYNTHETIC Pointer Events log (not a real
recording) of two pen strokes, as a web canvas logs pointerdown, pointermove
and pointerup events: timeStamp in ms at 120 Hz with a few events coalesced at
the same time stamp, offsetX/offsetY in CSS pixels, pressure, tiltX/tiltY
(the pen leaning right and towards the user, more as the stroke goes on),
twist, buttons and pointerType. It exercises the columns a real tablet
recording has (docs/input.md, "Pointer Events CSV"); the real recording is
painting30sec-excerpt.dat.

  python3 scenes/recordings/make_pointer_events.py > scenes/recordings/pointer-events.csv
"""
import math

print("timeStamp,type,pointerId,pointerType,offsetX,offsetY,pressure,tiltX,tiltY,twist,buttons")
t = 1000.0
def row(kind, x, y, p, tx, ty, tw, b):
    print(f"{t:.1f},{kind},1,pen,{x:.2f},{y:.2f},{p:.3f},{tx:.0f},{ty:.0f},{tw:.0f},{b}")

for stroke in range(2):
    y0 = 60 + 90 * stroke
    # Hovering in, 5 events.
    for k in range(5):
        row("pointermove", 40 + 4 * k, y0 - 12 + 2 * k, 0, 0, 0, 0, 0)
        t += 8.3
    n = 60
    for k in range(n + 1):
        u = k / n
        x = 60 + 300 * u
        y = y0 + 25 * math.sin(2 * math.pi * u)
        p = 0.15 + 0.5 * math.sin(math.pi * u)
        tx, ty = 10 + 30 * u, 5 + 15 * u * stroke
        row("pointerdown" if k == 0 else "pointermove", x, y, p, tx, ty, 20 * stroke, 1)
        if k % 20 == 10:  # a coalesced event at the same time stamp
            row("pointermove", x + 0.5, y, p, tx, ty, 20 * stroke, 1)
        t += 8.3
    row("pointerup", 362, y0, 0, 40, 5 + 15 * stroke, 20 * stroke, 0)
    t += 8.3
    for k in range(5):
        row("pointermove", 366 + 4 * k, y0 - 2 * k, 0, 0, 0, 0, 0)
        t += 8.3
    t += 250
