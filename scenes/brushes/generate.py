#!/usr/bin/env python3
"""Regenerates the brush library in this folder (bristle-brush/1 JSON).

Each brush is a few simulated spines (paper §3) plus its geometry (§4): a
Catmull-Clark control cage skinned to the spines (§4.1) and/or bristle strips
interpolated between them (§4.2). Sizes follow real brushes; stiffness,
friction and damping follow the calibration of §5 (K 5-10 N mm/rad, stiffer at
the ferrule; mu 0.3-0.5; D <= 0.01). Run: python3 generate.py
"""
import json
import math
import os
import re

HERE = os.path.dirname(os.path.abspath(__file__))


def bend_towards(alpha, bends):
    """Small-angle rest angles bending by b towards direction alpha in x-y:
    theta bends towards +y, phi towards -x (paper eq. 10)."""
    dx, dy = math.cos(alpha), math.sin(alpha)
    return [[round(b * dy, 4), round(-b * dx, 4)] for b in bends]


def spine(root, lengths, K, D, rest, widths):
    return {"root_mm": [round(v, 4) for v in root], "segment_lengths_mm": lengths,
            "stiffness_nmm_per_rad": K, "damping_nmm": D, "rest_angles_rad": rest,
            "width_mm": widths}


def rest_points(sp):
    """Joint positions at rest in the brush frame (eq. 10-11, handle identity)."""
    pts = [list(sp["root_mm"])]
    R = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
    for L, (th, ph) in zip(sp["segment_lengths_mm"], sp["rest_angles_rad"]):
        ct, st, cp, s_p = math.cos(th), math.sin(th), math.cos(ph), math.sin(ph)
        J = [[cp, s_p * st, s_p * ct], [0, ct, -st], [-s_p, cp * st, cp * ct]]
        R = [[sum(R[i][k] * J[k][j] for k in range(3)) for j in range(3)] for i in range(3)]
        d = [R[i][2] * -L for i in range(3)]
        pts.append([pts[-1][i] + d[i] for i in range(3)])
    return pts


def tube_cage(spines, ring, half_x, half_y, square_end=False):
    """A cage of rings around the spines, one ring per spine point level, closed
    by a tip vertex. half_x/half_y(k) give the half-extents of ring k beyond the
    spread of the spine points. Catmull-Clark pulls a ring of m vertices in to
    (4 + 2 cos(2 pi/m)) / 6 of its radius, so rings are grown by the inverse and
    the smooth surface encloses the spines. Every ring vertex is skinned to the
    two spine points of its level nearest to it (weights ~ 1/d^2); the tip
    vertex, half a tip width beyond the lowest tip (at its level for a
    square_end), to all tips equally, so
    that the surface's end stays over the spines however they splay."""
    levels = len(spines[0]["segment_lengths_mm"]) + 1
    pts = [rest_points(s) for s in spines]
    grow = 6 / (4 + 2 * math.cos(2 * math.pi / ring))
    verts, skin, faces = [], [], []
    for k in range(levels):
        level = [p[k] for p in pts]
        cx = sum(p[0] for p in level) / len(level)
        cy = sum(p[1] for p in level) / len(level)
        cz = sum(p[2] for p in level) / len(level)
        ax = (max(abs(p[0] - cx) for p in level) + half_x(k)) * grow
        # (A square end's flat sides hardly shrink under Catmull-Clark.)
        ay = (max(abs(p[1] - cy) for p in level) + half_y(k)) * (1 if square_end else grow)
        for r in range(ring):
            t = 2 * math.pi * r / ring
            # A square-cut flat's hair fills a rectangle with rounded ends (the
            # superellipse of exponent 4), not a lens: it is as thick at its
            # edges as in its middle, so its belly meets the paper along a
            # straight line.
            e = 0.5 if square_end else 1.0
            c_, s_ = math.cos(t), math.sin(t)
            v = [cx + ax * math.copysign(abs(c_) ** e, c_),
                 cy + ay * math.copysign(abs(s_) ** e, s_), cz]
            verts.append([round(c, 4) for c in v])
            d = sorted((math.hypot(v[0] - p[0], v[1] - p[1]), s) for s, p in enumerate(level))
            infl = d[:2] if len(d) > 1 else d
            w = [1 / (di * di + 1e-6) for di, _ in infl]
            tot = sum(w)
            ws = [round(x / tot, 4) for x in w]
            ws[0] = round(1 - sum(ws[1:]), 4)
            skin.append([[s, k, wi] for (_, s), wi in zip(infl, ws) if wi > 0])
    tips = [p[-1] for p in pts]
    tip = [sum(t[i] for t in tips) / len(tips) for i in range(3)]
    # A square-cut flat ends in a face at its tips, not a dome beyond them.
    tip[2] = min(t[2] for t in tips) - (0 if square_end else 0.5 * max(half_x(levels - 1), 0.2))
    verts.append([round(c, 4) for c in tip])
    n = len(spines)
    ws = [round(1 / n, 4)] * n
    ws[0] = round(1 - sum(ws[1:]), 4)
    skin.append([[s, levels - 1, ws[s]] for s in range(n)])
    for k in range(levels - 1):
        for r in range(ring):
            a, b = k * ring + r, k * ring + (r + 1) % ring
            faces.append([a, b, b + ring, a + ring])
    t = len(verts) - 1
    for r in range(ring):
        a, b = (levels - 1) * ring + r, (levels - 1) * ring + (r + 1) % ring
        faces.append([a, b, t])
    return {"cage_vertices_mm": verts, "faces": faces, "skin": skin, "refinement_level": 2}


def write(name, brush):
    s = json.dumps(brush, indent=2)
    # Keep short number arrays on one line.
    s = re.sub(r'\[\s+([-0-9.e,\s]+?)\s+\]',
               lambda m: '[' + ', '.join(x.strip() for x in m.group(1).split(',')) + ']', s)
    s = re.sub(r'\[\s+(\[[-0-9.e, ]+\](?:,\s+\[[-0-9.e, ]+\])*)\s+\]',
               lambda m: '[' + re.sub(r',\s+\[', ', [', m.group(1)) + ']', s)
    with open(os.path.join(HERE, name + ".json"), "w") as f:
        f.write(s + "\n")


def base(name, description, spines, mu_s, mu_k, aniso=0.0):
    return {"format": "bristle-brush/1", "name": name, "description": description,
            "spines": spines,
            "friction": {"mu_static": mu_s, "mu_kinetic": mu_k,
                         "anisotropy": {"strength": aniso, "exponent": 2}}}


def volume(tip_spread):
    """Hair volume (docs/dynamics.md): neighbouring spines keep 0.8 of their
    spacing at rest and, wet, hold within 1.3 times it (tip_spread: how far the
    converging tips may spread towards the belly's spacing). Measured in
    docs/fidelity.md: it fills a pressed round's star and a badger's ring."""
    return {"min_separation": 0.8, "stiffness_n_per_mm": 5, "max_separation": 1.3,
            "cohesion_n_per_mm": 1, "tip_spread": tip_spread}


def round_brush():
    lengths, K, D = [6.0, 5.5, 5.0, 3.5], [30.0, 12.0, 3.0, 0.8], [0.008, 0.006, 0.005, 0.004]
    # The six outer spines converge to the point; the centre one stands for the
    # belly's core and ends 1 mm inside it, so that it never stands on its own
    # tip ahead of theirs as the hair springs back at lift-off, nor props the
    # pressed point up on one side (docs/fidelity.md, "Artefacts").
    centre = lengths[:-1] + [lengths[-1] - 1.0]
    sp = [spine([0, 0, 0], centre, K, D, [[0.03, 0.0], [0, 0], [0, 0], [0, 0]],
                [3.2, 3.6, 3.2, 2.4, 0.8])]
    for k in range(6):
        a = math.pi / 6 + k * math.pi / 3
        sp.append(spine([1.7 * math.cos(a), 1.7 * math.sin(a), 0], lengths, K, D,
                        bend_towards(a, [0.04, 0.0, -0.2, -0.12]), [2.4, 2.8, 2.5, 1.8, 0.5]))
    b = base("round", "Round, size 8: 20 mm of hair, 5 mm across at the ferrule, fine point",
             sp, 0.45, 0.35, 0.3)
    belly = [0.9, 1.3, 1.1, 0.6, 0.25]
    b["surface"] = tube_cage(sp, 10, lambda k: belly[k], lambda k: belly[k])
    # Hair is nearly incompressible: pressed straight down, the squashed belly
    # spreads round the handle instead of laying over to one side
    # (docs/dynamics.md, "A squashed bundle spreads"; 40 N/mm, docs/fidelity.md,
    # "The round's press blot").
    b["volume"] = dict(volume(0.45), spread_n_per_mm=40)
    b["paint"] = {"capacity": 1.0}
    return b


def flat_row(name, desc, width, thick, lengths, K, n_spines, strips, tip_curve=0.0,
             surface=True, mu=(0.45, 0.35), square_end=False):
    D = [0.008] + [0.006] * (len(lengths) - 1)
    sp = []
    for i in range(n_spines):
        x = -width / 2 + width * (i + 0.5) / n_spines
        f = abs(x) / (width / 2)
        # A filbert's outer hairs are shorter: the tip is an oval.
        ls = [round(L * (1 - tip_curve * f * f), 3) for L in lengths]
        rest = [[0.02, 0.0]] + [[0, 0]] * (len(lengths) - 1)
        wseg = width / n_spines * 1.15
        # A square-cut flat keeps its width to the tip; a filbert's tips narrow.
        tip_w = wseg if square_end else wseg * 0.7
        s = spine([x, 0, 0], ls, K, D, rest, [round(wseg, 3)] * len(lengths) + [round(tip_w, 3)])
        # Each spine of a square-cut flat stands for a slab of the row: as
        # wide as its share of the row, as thick as the brush, thinning
        # towards the chisel edge. (A filbert's narrowing tips stay round.)
        if square_end:
            s["thickness_mm"] = [round(thick * (1 - 0.5 * k / len(lengths)), 3)
                                 for k in range(len(lengths) + 1)]
        sp.append(s)
    b = base(name, desc, sp, *mu, 0.3)
    if surface:
        b["surface"] = tube_cage(sp, 12, lambda k: width / n_spines * 0.6,
                                 lambda k: thick / 2 * (1 - 0.5 * k / len(lengths)),
                                 square_end)
    if strips:
        b["strips"] = {"count": strips, "root_width_mm": 0.15, "tip_width_mm": 0.06,
                       "seed": 11, "placement": "line", "length_jitter": 0.08}
    b["paint"] = {"capacity": 1.2}
    return b


# Badger: spine stiffness (N mm/rad, root to tip), bundle widths (mm) of the
# centre and the outer spines, paint capacity and flag length (mm).
K_BADGER = [3.0, 2.5, 2.0, 2.0]
BADGER_WIDTHS = ([5.0, 6.0, 6.0, 5.5, 4.5], [3.5, 4.5, 4.5, 4.0, 3.5])
BADGER_CAPACITY = 0.6
BADGER_FLAG_MM = 1.5
# The radius (mm) of the sphere the badger's hair ends are cut to.
BADGER_DOME_MM = 13.0
# The load (N) that presses a badger's bundle flat: a fifth of the library's
# 0.05 N (kBundleFlatLoadN). Its hair is the finest and softest of the
# library's and splays at a touch; at 0.05 of its hair (1.25 mm of press) its
# spines bear 0.005-0.015 N each, enough to lay their bundles down side by side.
BADGER_FLAT_LOAD_N = 0.01


def badger():
    """A badger softener: a dense dome of fine flagged hair. Its hair is as
    full at the end as at the belly (the dome is cut, not pointed), so each
    spine's bundle stays wide to its tip and neighbouring bundles overlap: the
    hair meets the paper as one mass, not as fingers. It is soft and bends
    under a light touch (K about half the round's belly), and its flagged
    ends (paint.flag_mm) lay a thin, broken film at the rim of what touches
    (docs/brush-format.md, "Flagged hair")."""
    lengths, K, D = [8.0, 7.0, 6.0, 4.0], K_BADGER, [0.01] * 4
    sp = [spine([0, 0, 0], lengths, K, D, [[0.03, 0.0], [0, 0], [0, 0], [0, 0]],
                BADGER_WIDTHS[0])]
    tip_z = -rest_points(sp[0])[-1][2]
    for ring, (r, count) in enumerate([(3.2, 6), (6.0, 8)]):
        for k in range(count):
            a = 2 * math.pi * k / count + ring * 0.3
            s = spine([r * math.cos(a), r * math.sin(a), 0], lengths, K, D,
                      bend_towards(a, [0.06 + 0.04 * ring, 0.0, -0.1, -0.05]),
                      BADGER_WIDTHS[1])
            # The head is domed: its hair ends lie on a sphere of radius
            # BADGER_DOME_MM, so the outer hair is shorter by the sphere's sag
            # at its tip. Tilted as it is held, the dome still meets the paper
            # over a patch (radius sqrt(2 R d) pressed d deep), where a flat-cut
            # head would meet it with its rim's two or three tips only.
            x, y, z = rest_points(s)[-1]
            sag = BADGER_DOME_MM - math.sqrt(BADGER_DOME_MM ** 2 - x * x - y * y)
            f = (tip_z - sag) / -z
            s["segment_lengths_mm"] = [round(L * f, 3) for L in lengths]
            sp.append(s)
    for s in sp:
        # Its soft hair bears load before the joints reach the paper, so that
        # the dome's first touch lays a haze (docs/brush-format.md).
        s["flat_load_n"] = BADGER_FLAT_LOAD_N
        s["bundle_bears_load"] = True
    b = base("badger", "Badger softener: a soft dome of flagged hair, 14 mm across, 25 mm long",
             sp, 0.4, 0.3, 0.2)
    b["surface"] = tube_cage(sp, 12, lambda k: 1.2, lambda k: 1.2)
    b["strips"] = {"count": 300, "root_width_mm": 0.12, "tip_width_mm": 0.05, "seed": 5,
                   "placement": "area", "length_jitter": 0.15}
    b["volume"] = volume(0.3)
    # A softener holds a thin film (capacity) and lays it thinner still where
    # only its flags touch; it is worked nearly clean to blend paint already down.
    # Its hair does not wick (wicking 0): what it lifts from wet paint stays at
    # its ends and is laid again further on, so it moves paint, not scrubs it;
    # its load still runs down to the tips (docs/paint.md, "Unabsorbent hair").
    b["paint"] = {"capacity": BADGER_CAPACITY, "flag_mm": BADGER_FLAG_MM, "wicking": 0.0}
    return b


def fan():
    # Five segments, shorter towards the tip. A spine bends only at its joints
    # and only its joints are held above the paper (eq. 5), so the last segment
    # is a straight stick standing on its tip: with the old 3 segments (8, 8,
    # 6 mm) the joint before a touching tip stood 2.9 mm above the paper on the
    # standard s-curve (+2 mm) and each hair met the 0.1 mm contact band over
    # ~0.2 mm only. With 3 mm tip segments that joint stands 1.3 mm high.
    lengths, K = [6.0, 5.0, 4.5, 3.5, 3.0], [8.0, 7.0, 6.0, 5.5, 5.0]
    D = [0.004] * len(lengths)
    sp = []
    n = 7
    for i in range(n):
        x = -6 + 12 * i / (n - 1)
        # Splayed: the hairs leave the flat ferrule fanning out to a ~30 mm span.
        a = math.atan2(0, 1) if x >= 0 else math.pi
        spread = abs(x) / 6 * 0.55
        # Each spine is one hair of the fan: as thin as its strips.
        sp.append(spine([x, 0, 0], lengths, K, D, bend_towards(a, [spread, 0.0, 0.0, 0.0, 0.0]),
                        [0.2, 0.18, 0.16, 0.13, 0.1, 0.06]))
    b = base("fan", "Fan: a thin, splayed row of hair, ~30 mm span, 22 mm long", sp, 0.4, 0.3, 0.3)
    # No length jitter: a fan's hairs are cut to one even arc, and its marks are
    # the lines its hair tips draw. A strip follows its spines' path (eq. 16), so
    # a strip shortened by f ends where the spines are (1 - f) * 22 mm from their
    # tips: on a tip segment rising at 25-40 degrees, 1 % shorter is already out
    # of the 0.1 mm contact band. With the old jitter of 0.12, 146 of 160 strips
    # never reached the paper.
    # Wet, a fan's hairs gather into bunches that draw distinct lines (the
    # grass stroke): 12 bunches of ~13 strips, drawn 80 % of the way together
    # at the tips.
    b["strips"] = {"count": 160, "root_width_mm": 0.14, "tip_width_mm": 0.05, "seed": 3,
                   "placement": "line", "length_jitter": 0.0, "clumps": 12, "clumping": 0.8}
    b["paint"] = {"capacity": 0.8}
    # Ipopt reaches the fan's equilibria in fewer iterations with friction as
    # constrained variables: its seven hairs slide and stick one by one, and
    # in the objective form each sticking hair's kink costs line-search cuts
    # (docs/dynamics.md, "Friction in epigraph form"). The brushes without
    # hair volume otherwise keep the objective form.
    b["solver"] = {"friction_form": "epigraph"}
    return b


def calligraphy():
    # The point's last 4 mm in two segments, so that its hair meets the paper
    # a little at a time: as one rigid 4 mm segment it lay down at once
    # between 3.5 and 4 mm of press, and an upright pull's width jumped from
    # 2.4 to 3.6 mm there (docs/fidelity.md, "Entries and blots").
    lengths = [7.0, 7.0, 6.5, 5.5, 2.0, 2.0]
    # Graded stiffness (docs/dynamics.md, "Graded stiffness"): a stiff root
    # and a soft belly and tip, so that a press lays the belly down.
    K, D = [60.0, 15.0, 4.0, 1.2, 0.8, 0.5], [0.01, 0.008, 0.006, 0.005, 0.004, 0.004]
    # The belly's bundles, widened 1.15-1.5x from the root so that the laid
    # belly covers the paper between spines as a real brush's hair does. The
    # lower belly and the tip are as full as the real 30 mm brush of
    # data/real-brushes/wang2020-calligraphy.csv: its stroke is 1.8 mm wide at
    # 1 mm of press, 3 mm at 3 mm and 5-5.5 mm at 5 mm (docs/fidelity.md,
    # "Real brushes"), so its hair 4 mm from the tip is ~3 mm across, not a
    # needle's point. The point's new joint halves the old tip segment's taper.
    # The centre spine is straight at rest: a brush has no preferred side, so
    # that a press lays it over the way the handle moves (with a rest angle
    # it lay over one way whatever the stroke's direction, and an entry's
    # head sat beside the stroke's line).
    sp = [spine([0, 0, 0], lengths, K, D, [[0.0, 0.0]] * 6,
                [4.5, 6.32, 6.5, 7.35, 4.41, 2.805, 1.2])]
    for k in range(6):
        a = math.pi / 6 + k * math.pi / 3
        # The belly gathers the hair into the point (-0.18, -0.14) and the
        # point's segments turn back (0.1, 0.22), so that its last 2 mm hang
        # about straight down (0.07 rad out) instead of pointing in at the
        # axis: inward-pointing tips, pressed, push each spine's belly
        # outwards and the bundle splays round its point into a bead.
        sp.append(spine([2.6 * math.cos(a), 2.6 * math.sin(a), 0], lengths, K, D,
                        bend_towards(a, [0.05, 0.02, -0.18, -0.14, 0.1, 0.22]),
                        [3.2, 4.37, 4.42, 5.46, 2.94, 1.92, 0.9]))
    b = base("calligraphy", "Oriental calligraphy brush: 30 mm long, 8 mm at the ferrule, "
             "fine tip, soft", sp, 0.4, 0.3, 0.4)
    belly = [1.2, 1.8, 1.6, 1.0, 0.4, 0.3, 0.2]
    b["surface"] = tube_cage(sp, 10, lambda k: belly[k], lambda k: belly[k])
    b["strips"] = {"count": 150, "root_width_mm": 0.12, "tip_width_mm": 0.04, "seed": 9,
                   "placement": "area", "length_jitter": 0.1}
    # A wet calligraphy brush is one body of hair: ink binds its tips into the
    # point, so that its entry is one rounded head (docs/dynamics.md, "Hair
    # volume"). Cohesion (1.1 times the spacing at rest, no tip spread) keeps
    # the pressed tips from fanning out into fingers; neighbours may squeeze
    # to 0.3 of their spacing, as wet hair packs, so that a dwell's press does
    # not push them apart either. Pressed straight down past its point, the
    # belly is squashed and spreads round the handle (spread_n_per_mm); the
    # first 5 mm of a press only lay the soft point down (squash_after_mm).
    # Cohesion at 3 N/mm lets the spread win: at 20 the bundle lay over to one
    # side as one body (docs/dynamics.md, "The point lies down before the
    # belly squashes"). The spread's push grows to its full stiffness over
    # the first 0.05 of squash (spread_ramp), about 1.2 mm of press: switched
    # on whole, it threw the laid-down point across the axis in one step and
    # the solver split its steps ninefold (docs/dynamics.md, "The spread
    # ramps in").
    b["volume"] = dict(volume(0.0), min_separation=0.3, stiffness_n_per_mm=2,
                       max_separation=1.1, cohesion_n_per_mm=3, spread_n_per_mm=40,
                       squash_after_mm=5, spread_ramp=0.05)
    b["paint"] = {"capacity": 1.3}
    return b


if __name__ == "__main__":
    write("round", round_brush())
    write("flat", flat_row("flat", "Flat, 1/2 inch: 12 mm wide, 16 mm long, square end",
                           12.0, 3.0, [6.0, 5.5, 4.5], [10.0, 8.0, 6.0], 5, 120,
                           square_end=True))
    write("bright", flat_row("bright", "Bright: the flat's 12 mm width, 11 mm long, stiffer",
                             12.0, 3.0, [4.5, 3.5, 3.0], [10.0, 9.0, 7.0], 5, 100,
                             square_end=True))
    write("filbert", flat_row("filbert", "Filbert: 10 mm wide, 15 mm long, oval tip",
                              10.0, 3.0, [6.0, 5.0, 4.0], [10.0, 8.0, 6.0], 5, 120,
                              tip_curve=0.35))
    write("badger", badger())
    write("fan", fan())
    write("calligraphy", calligraphy())
