#!/usr/bin/env python3
"""Regenerates the batch manifests in this folder (bristle-batch/1).

standard.json: every library brush on the standard stroke set (straight pull,
S-curve, press-lift, tilted drag), in their depth/ form: heights given as press
depth past each brush's first contact (docs/formats.md, "Heights relative to
the paper"), so that every brush meets the paper as deep as the others, with no
lift per brush.
demo.json: what scripts/demo renders besides the paintings and the three
traced strokes (a batch job writes only its PNG): the library stroke sheet,
every library brush along the S-curve with its faster solver, and a 3D preview of each
brush, at rest, and of the round deformed 1.2 s into the S-curve.

Run from anywhere: python3 generate.py
"""
import json
import os

HERE = os.path.dirname(os.path.abspath(__file__))
BRUSHES = ["round", "flat", "bright", "filbert", "badger", "fan", "calligraphy"]
STROKES = ["straight-pull", "s-curve", "press-lift", "tilted-drag"]
# The demo's S-curves take SLSQP where it is the faster solver: brushes whose
# spines hair volume does not couple, and the badger, whose 15 it sweeps one
# at a time. The round and the calligraphy brush take Ipopt: SLSQP solves
# their coupled spines as one dense block, several times Ipopt's CPU
# (docs/PERFORMANCE.md, "SLSQP's block solve").
IPOPT_FASTER = {"round", "calligraphy"}


def standard():
    jobs = []
    for b in BRUSHES:
        for t in STROKES:
            jobs.append({"id": f"{b}-{t}", "brush": f"../brushes/{b}.json",
                         "trajectory": f"../trajectories/depth/{t}.csv"})
    return {"format": "bristle-batch/1", "jobs": jobs}


def paintings():
    """The three paintings, flat and with impasto: what scripts/demo renders."""
    jobs = []
    for p in ["petals", "calligraphy", "landscape"]:
        jobs.append({"id": f"painting-{p}", "scene": f"../paintings/{p}.json"})
        jobs.append({"id": f"painting-{p}-impasto", "scene": f"../paintings/{p}.json",
                     "options": {"impasto": True}})
    return {"format": "bristle-batch/1", "jobs": jobs}


def demo():
    """scripts/demo's renders as batch jobs, so that a second demo run skips what
    is up to date. The sheet comes first: at about 2 minutes with Ipopt it is
    the longest job, and starting it first keeps the other workers busy beside it."""
    jobs = [{"id": "sheet-library", "sheet": "../sheets/library.json"}]
    for b in BRUSHES:
        # The S-curve in press depths: each brush as deep past its own first
        # contact, none lifted by hand.
        jobs.append({"id": f"library-{b}", "brush": f"../brushes/{b}.json",
                     "trajectory": "../trajectories/depth/s-curve.csv",
                     "options": {"solver": "ipopt" if b in IPOPT_FASTER else "slsqp"}})
        jobs.append({"id": f"preview-{b}", "preview": f"../brushes/{b}.json"})
    jobs.append({"id": "preview-round-1.2s", "preview": "../brushes/round.json",
                 "trajectory": "../trajectories/s-curve.csv", "options": {"at": 1.2}})
    return {"format": "bristle-batch/1", "jobs": jobs}


if __name__ == "__main__":
    for name, manifest in [("standard.json", standard()), ("paintings.json", paintings()),
                           ("demo.json", demo())]:
        with open(os.path.join(HERE, name), "w") as f:
            f.write(json.dumps(manifest, indent=2) + "\n")
