#!/usr/bin/env python3
"""Regenerates the batch manifests in this folder (bristle-batch/1).

standard.json: every library brush on the standard stroke set (straight pull,
S-curve, press-lift, tilted drag). The trajectories are written for the 20 mm
round; each brush's handle is raised or lowered by the difference of its hair
length (--offset-mm 0 0 dz), so every brush meets the paper at the same depth
a round does. Without it the 30 mm calligraphy brush would start inside the
paper and the 11 mm bright would never reach it. The handle is lowered by at
most 6 mm: the S-curve's deepest press brings a 20 mm round's handle to 9 mm
above the paper, and the bright's ferrule (lowered the full 9 mm) would dig in.
demo.json: what scripts/demo renders besides the paintings and the three
traced strokes (a batch job writes only its PNG): the library stroke sheet,
every library brush along the S-curve with SLSQP, and a 3D preview of each
brush, at rest, and of the round deformed 1.2 s into the S-curve.

Run from anywhere: python3 generate.py
"""
import json
import os

HERE = os.path.dirname(os.path.abspath(__file__))
BRUSHES = ["round", "flat", "bright", "filbert", "badger", "fan", "calligraphy"]
STROKES = ["straight-pull", "s-curve", "press-lift", "tilted-drag"]
REFERENCE_HAIR_MM = 20.0  # the round, which the trajectories were written for
MAX_LOWERING_MM = 6.0     # keeps the S-curve's ferrule 3 mm above the paper


def hair_length_mm(brush):
    with open(os.path.join(HERE, "..", "brushes", brush + ".json")) as f:
        spines = json.load(f)["spines"]
    return max(sum(s["segment_lengths_mm"]) - s["root_mm"][2] for s in spines)


def standard():
    jobs = []
    for b in BRUSHES:
        dz = round(max(hair_length_mm(b) - REFERENCE_HAIR_MM, -MAX_LOWERING_MM), 3)
        for t in STROKES:
            job = {"id": f"{b}-{t}", "brush": f"../brushes/{b}.json",
                   "trajectory": f"../trajectories/{t}.csv"}
            if dz != 0:
                job["options"] = {"offset-mm": [0, 0, dz]}
            jobs.append(job)
    return {"format": "bristle-batch/1", "jobs": jobs}


def paintings():
    """The three paintings, flat and with impasto: what scripts/demo renders."""
    jobs = []
    for p in ["petals", "calligraphy", "landscape"]:
        jobs.append({"id": f"painting-{p}", "scene": f"../paintings/{p}.json"})
        jobs.append({"id": f"painting-{p}-impasto", "scene": f"../paintings/{p}.json",
                     "options": {"impasto": True}})
    return {"format": "bristle-batch/1", "jobs": jobs}


# The demo's handle lift per brush (mm): the S-curve was written for the 20 mm
# round; the longer badger and calligraphy brushes are held higher. (Not the
# hair-length rule of standard(): these are the lifts the demo has always used.)
DEMO_LIFT_MM = {"badger": 6, "calligraphy": 9}


def demo():
    """scripts/demo's renders as batch jobs, so that a second demo run skips what
    is up to date. The sheet comes first: at about 2 minutes with Ipopt it is
    the longest job, and starting it first keeps the other workers busy beside it."""
    jobs = [{"id": "sheet-library", "sheet": "../sheets/library.json"}]
    for b in BRUSHES:
        options = {"solver": "slsqp"}
        if DEMO_LIFT_MM.get(b, 0):
            options["offset-mm"] = [0, 0, DEMO_LIFT_MM[b]]
        jobs.append({"id": f"library-{b}", "brush": f"../brushes/{b}.json",
                     "trajectory": "../trajectories/s-curve.csv", "options": options})
        jobs.append({"id": f"preview-{b}", "preview": f"../brushes/{b}.json"})
    jobs.append({"id": "preview-round-1.2s", "preview": "../brushes/round.json",
                 "trajectory": "../trajectories/s-curve.csv", "options": {"at": 1.2}})
    return {"format": "bristle-batch/1", "jobs": jobs}


if __name__ == "__main__":
    for name, manifest in [("standard.json", standard()), ("paintings.json", paintings()),
                           ("demo.json", demo())]:
        with open(os.path.join(HERE, name), "w") as f:
            f.write(json.dumps(manifest, indent=2) + "\n")
