#!/usr/bin/env python3
# Tests of the Blender brush exporter/importer (scripts/blender/bristle_brush.py),
# run with Debian's Blender headless. scripts/test-blender runs them:
#
#   BLENDER=blender BRISTLE=build/cli/bristle python3 -m unittest -v scripts/blender/test_bristle_brush.py
#
# What they check:
#   - a brush modelled programmatically in Blender (tests/make_fixtures.py: in metres,
#     armature moved and turned, some properties on pose bones) exports to the brush it
#     was designed as, passes `bristle validate`, and paints a stroke;
#   - every library brush (scenes/brushes/*.json) imports, survives a .blend save and
#     load, and exports to an equivalent brush;
#   - posing the imported bones deforms the cage in Blender the way bristle skins it;
#   - the add-on registers its File menu entries and its operators work;
#   - bad models fail with a non-zero exit code and a one-line message naming the
#     object, bone or property; fixable ones export with a warning.

import concurrent.futures
import glob
import json
import os
import shutil
import struct
import subprocess
import tempfile
import unittest
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
SCRIPT = os.path.join(HERE, "bristle_brush.py")
BLENDER = os.environ.get("BLENDER", "blender")
BRISTLE = os.environ.get("BRISTLE", os.path.join(ROOT, "build", "cli", "bristle"))
LIBRARY = sorted(glob.glob(os.path.join(ROOT, "scenes", "brushes", "*.json")))
TRAJECTORY = os.path.join(ROOT, "scenes", "trajectories", "straight-pull.csv")

# Tolerances of "the same brush" after a trip through Blender.
# Blender stores bone ends and cage vertices as float32 (24-bit mantissa). The
# exporter rounds lengths to 1e-5 mm; a float32 coordinate of at most 64 mm is off
# by <= 3.8e-6 mm, and a length from two of them by <= 7.6e-6 mm: under 1e-5 mm.
LENGTH_TOL_MM = 1e-5
# Rest angles come from bone directions. Over the shortest library segment (3 mm),
# the float32 error of each end (<= 3.8e-6 mm) turns a direction by <= 2.5e-6 rad;
# a relative angle combines two directions (5e-6 rad), and rounding to 1e-6 rad
# adds 5e-7: 1e-5 rad holds with a margin of ~2.
ANGLE_TOL_RAD = 1e-5
# Cage vertices of the hand-made brush also pass through the armature's world
# transform (5 cm away, turned by 30 degrees) and back, in float32: a few units
# in the last place of 50 mm (3.7e-6 mm each). Library cages have identity
# transforms, so they are held to LENGTH_TOL_MM.
HANDMADE_CAGE_TOL_MM = 5e-5
# Skin weights are float32 in a vertex group (rel. error 6e-8) and rounded to 1e-6.
WEIGHT_TOL = 1e-6
# Stiffness, damping, friction, strips and paint are custom properties, which
# Blender keeps as doubles: they must come back exactly.

# Defaults of the brush format (docs/brush-format.md §3), applied to both sides of
# a comparison so that "absent" and "the default value" compare equal.
FRICTION_DEFAULT = {"mu_static": 0.4, "mu_kinetic": 0.35, "anisotropy": {"strength": 0.0, "exponent": 2.0}}
STRIPS_DEFAULTS = {"root_width_mm": 0.15, "tip_width_mm": 0.05, "seed": 1, "placement": "auto",
                   "length_jitter": 0.0}


def normalised(brush):
    """A copy of brush with every optional key filled in with its default."""
    b = json.loads(json.dumps(brush))
    b.setdefault("description", "")
    for s in b["spines"]:
        n = len(s["segment_lengths_mm"])
        s.setdefault("damping_nmm", [0.0] * n)
        s.setdefault("rest_angles_rad", [[0.0, 0.0]] * n)
    if "friction" not in b:
        b["friction"] = json.loads(json.dumps(FRICTION_DEFAULT))
    f = b["friction"]
    f.setdefault("mu_kinetic", f["mu_static"])
    f.setdefault("anisotropy", {"strength": 0.0})
    f["anisotropy"].setdefault("exponent", 2.0)
    if "surface" in b:
        b["surface"].setdefault("refinement_level", 2)
    if "strips" in b:
        for k, v in STRIPS_DEFAULTS.items():
            b["strips"].setdefault(k, v)
    b.setdefault("paint", {"capacity": 1.0})
    return b


def differences(got, want, cage_tol=LENGTH_TOL_MM):
    """Where got and want differ beyond the tolerances, as 'pointer: got vs want'."""
    got, want = normalised(got), normalised(want)
    out = []

    def close(path, a, b, tol):
        if isinstance(a, list) or isinstance(b, list):
            if not (isinstance(a, list) and isinstance(b, list)) or len(a) != len(b):
                out.append("%s: %r vs %r" % (path, a, b))
                return
            for i, (x, y) in enumerate(zip(a, b)):
                close("%s/%d" % (path, i), x, y, tol)
        elif tol is None:
            if a != b:
                out.append("%s: %r vs %r" % (path, a, b))
        elif not abs(a - b) <= tol:
            out.append("%s: %r vs %r (tolerance %g)" % (path, a, b, tol))

    # Every block the file has comes back: a block the exporter does not know
    # would otherwise be dropped without a word.
    close("/ (keys)", sorted(got), sorted(want), None)
    for key in ("format", "name", "description", "friction", "strips", "volume", "paint", "solver"):
        close("/" + key, got.get(key), want.get(key), None)  # 2 == 2.0: numbers by value
    close("/spines", len(got["spines"]), len(want["spines"]), None)
    for i, (g, w) in enumerate(zip(got["spines"], want["spines"])):
        p = "/spines/%d/" % i
        close(p + "root_mm", g["root_mm"], w["root_mm"], LENGTH_TOL_MM)
        close(p + "segment_lengths_mm", g["segment_lengths_mm"], w["segment_lengths_mm"], LENGTH_TOL_MM)
        close(p + "width_mm", g["width_mm"], w["width_mm"], LENGTH_TOL_MM)
        close(p + "thickness_mm", g.get("thickness_mm", "round"), w.get("thickness_mm", "round"),
              LENGTH_TOL_MM if "thickness_mm" in w else None)
        close(p + "rest_angles_rad", g["rest_angles_rad"], w["rest_angles_rad"], ANGLE_TOL_RAD)
        close(p + "stiffness_nmm_per_rad", g["stiffness_nmm_per_rad"], w["stiffness_nmm_per_rad"], None)
        close(p + "damping_nmm", g["damping_nmm"], w["damping_nmm"], None)
    close("/surface", "surface" in got, "surface" in want, None)
    if "surface" in got and "surface" in want:
        g, w = got["surface"], want["surface"]
        close("/surface/cage_vertices_mm", g["cage_vertices_mm"], w["cage_vertices_mm"], cage_tol)
        close("/surface/faces", g["faces"], w["faces"], None)
        close("/surface/refinement_level", g["refinement_level"], w["refinement_level"], None)
        close("/surface/skin", len(g["skin"]), len(w["skin"]), None)
        for v, (gs, ws) in enumerate(zip(g["skin"], w["skin"])):
            # Same (spine, point) influences, weights within WEIGHT_TOL; order free.
            gd = {(s, p): wt for s, p, wt in gs}
            wd = {(s, p): wt for s, p, wt in ws}
            close("/surface/skin/%d influences" % v, sorted(gd), sorted(wd), None)
            if sorted(gd) == sorted(wd):
                close("/surface/skin/%d weights" % v, [gd[k] for k in sorted(gd)],
                      [wd[k] for k in sorted(wd)], WEIGHT_TOL)
    return out


def read_png(path):
    """(width, height, rows of (r, g, b)) of an 8-bit RGB/RGBA, non-interlaced PNG."""
    with open(path, "rb") as f:
        data = f.read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", path
    pos, idat = 8, b""
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            width, height, depth, ctype, _, _, interlace = struct.unpack(">IIBBBBB", body)
            assert depth == 8 and ctype in (2, 6) and interlace == 0, (depth, ctype, interlace)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    bpp = 3 if ctype == 2 else 4
    raw = zlib.decompress(idat)
    stride = width * bpp
    rows, prev = [], bytearray(stride)
    for y in range(height):
        ftype = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b = prev[i]
            c = prev[i - bpp] if i >= bpp else 0
            if ftype == 1:
                line[i] = (line[i] + a) & 255
            elif ftype == 2:
                line[i] = (line[i] + b) & 255
            elif ftype == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif ftype == 4:
                pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
                pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                line[i] = (line[i] + pred) & 255
        rows.append([tuple(line[x * bpp:x * bpp + 3]) for x in range(width)])
        prev = line
    return width, height, rows


def _run_blender(args, blend, script):
    cmd = [BLENDER, "-b", "--factory-startup"] + ([blend] if blend else []) + \
        ["--python-exit-code", "1", "--python", script, "--"] + args
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=120)
    return p.returncode, p.stdout, p.stderr


# Blender runs started ahead of the tests that read them (see prefetch()).
_STARTED = {}


def run_blender(args, blend=None, script=SCRIPT):
    """(exit code, stdout, stderr) of a headless Blender run of script with args;
    the result of the same run if prefetch() started it already."""
    key = (tuple(args), blend, script)
    if key in _STARTED:
        return _STARTED.pop(key).result()
    return _run_blender(args, blend, script)


def prefetch(runs):
    """Start independent Blender runs now, one per core, so their ~1 s start-ups
    overlap; each test still calls run_blender() with its own arguments."""
    pool = concurrent.futures.ThreadPoolExecutor(max_workers=os.cpu_count() or 2)
    for args, blend, script in runs:
        _STARTED[(tuple(args), blend, script)] = pool.submit(_run_blender, args, blend, script)
    pool.shutdown(wait=False)


REFUSED = ["no-armature", "branching", "no-groups", "stray-group", "scaled", "bad-friction",
           "misspelt-prop", "bad-stiffness", "two-armatures", "ngon", "root-above"]
FIXABLE = ["unnormalised", "missing-props", "modifier-order", "auto-weights"]


def messages(stderr):
    return [l for l in stderr.splitlines() if l.startswith("bristle_brush:")]


def run_bristle(args):
    p = subprocess.run([BRISTLE] + args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                       timeout=300)
    return p.returncode, p.stdout, p.stderr


TMP = None


def setUpModule():
    global TMP
    TMP = tempfile.mkdtemp(prefix="bristle-blender-test-")
    rc, out, err = run_blender([TMP], script=os.path.join(HERE, "tests", "make_fixtures.py"))
    if rc != 0:
        raise RuntimeError("make_fixtures.py failed (%d): %s" % (rc, err[-2000:]))
    # In the order unittest runs the classes (alphabetical) that read them.
    prefetch([([os.path.join(TMP, c + ".json")], fixture(c), SCRIPT) for c in REFUSED] +
             [(["--armature", "second", os.path.join(TMP, "second.json")], fixture("two-armatures"),
               SCRIPT)] +
             [([os.path.join(TMP, c + ".json")], fixture(c), SCRIPT) for c in FIXABLE] +
             [([os.path.join(TMP, n)], fixture("handmade"), SCRIPT)
              for n in ("handmade.json", "handmade-again.json")] +
             [([os.path.join(TMP, "posed.json")], fixture("posed"), SCRIPT)] +
             [(LIBRARY, None, os.path.join(HERE, "tests", "check_skinning.py"))])


def tearDownModule():
    shutil.rmtree(TMP, ignore_errors=True)


def fixture(case):
    return os.path.join(TMP, case + ".blend")


class HandMadeBrush(unittest.TestCase):
    """A brush modelled in Blender the way a user would, from design numbers."""

    @classmethod
    def setUpClass(cls):
        cls.out = os.path.join(TMP, "handmade.json")
        cls.rc, _, cls.err = run_blender([cls.out], blend=fixture("handmade"))

    def test_exports_the_designed_brush(self):
        self.assertEqual(self.rc, 0, self.err)
        self.assertEqual(messages(self.err), [], "a complete model exports without warnings")
        with open(self.out) as f:
            got = json.load(f)
        with open(os.path.join(TMP, "handmade.expected.json")) as f:
            want = json.load(f)
        self.assertEqual(differences(got, want, cage_tol=HANDMADE_CAGE_TOL_MM), [])
        # The tip vertex is weighted to the last bones, and lies past their middle:
        # it is skinned to the tips (point 3), as designed.
        self.assertEqual([p for _, p, _ in got["surface"]["skin"][-1]], [3, 3, 3])

    def test_export_is_deterministic(self):
        again = os.path.join(TMP, "handmade-again.json")
        rc, _, err = run_blender([again], blend=fixture("handmade"))
        self.assertEqual(rc, 0, err)
        with open(self.out, "rb") as a, open(again, "rb") as b:
            self.assertEqual(a.read(), b.read())

    def test_pose_is_ignored(self):
        # The same model with every bone posed exports the rest shape, byte for byte.
        posed = os.path.join(TMP, "posed.json")
        rc, _, err = run_blender([posed], blend=fixture("posed"))
        self.assertEqual(rc, 0, err)
        with open(self.out, "rb") as a, open(posed, "rb") as b:
            self.assertEqual(a.read(), b.read())

    def test_validates_and_paints(self):
        self.assertEqual(self.rc, 0, self.err)
        rc, out, err = run_bristle(["validate", self.out])
        self.assertEqual(rc, 0, err)
        self.assertIn("3 spines, surface, 80 strips", out)
        png = os.path.join(TMP, "handmade.png")
        rc, _, err = run_bristle(["render", "--brush", self.out, "--trajectory", TRAJECTORY, "-o", png])
        self.assertEqual(rc, 0, err)
        width, height, rows = read_png(png)
        paper = rows[0][0]  # the canvas has a 5 mm margin: the corner is bare paper
        # Ink: a pixel whose summed RGB is more than 60 levels below the paper
        # (the default paint is a dark blue, ~480 levels darker; paper grain varies
        # the paper by a few levels).
        ink = [(x, y) for y, row in enumerate(rows) for x, px in enumerate(row)
               if sum(paper) - sum(px) > 60]
        self.assertGreater(len(ink), 0)
        px_per_mm = 8.0  # bristle render's default --px-per-mm
        xs = [x for x, _ in ink]
        ys = [y for _, y in ink]
        # straight-pull.csv pulls the brush 55 mm along +x while pressing it down:
        # the mark must run most of that way (40 mm allows for the press-in and
        # lift-off ends) and be at least 1 mm wide (the root widths are 2.4 mm).
        self.assertGreater((max(xs) - min(xs)) / px_per_mm, 40.0)
        self.assertGreater((max(ys) - min(ys)) / px_per_mm, 1.0)


class LibraryRoundTrip(unittest.TestCase):
    """Import each library brush, save the .blend, reopen it, export: the same brush."""

    def test_every_library_brush(self):
        # The glob found the library: its seven hand-made brushes and the fitted ones.
        self.assertGreaterEqual(len(LIBRARY), 8)
        lib = os.path.join(TMP, "library")
        os.makedirs(lib, exist_ok=True)
        script = os.path.join(HERE, "tests", "round_trip.py")
        rc, _, err = run_blender(["import", lib] + LIBRARY, script=script)
        self.assertEqual(rc, 0, err)
        names = [os.path.splitext(os.path.basename(p))[0] for p in LIBRARY]
        rc, _, err = run_blender(["export", lib] + [os.path.join(lib, n + ".blend") for n in names],
                                 script=script)
        self.assertEqual(rc, 0, err)
        # Library brushes have every parameter: nothing to warn about.
        self.assertEqual(messages(err), [])
        exported = []
        for path, name in zip(LIBRARY, names):
            with self.subTest(brush=name):
                out = os.path.join(lib, name + ".json")
                with open(path) as f:
                    want = json.load(f)
                with open(out) as f:
                    got = json.load(f)
                self.assertEqual(differences(got, want), [])
                exported.append(out)
        rc, out, err = run_bristle(["validate"] + exported)
        self.assertEqual(rc, 0, err)
        self.assertEqual(out.count(": ok"), len(LIBRARY), out)

    def test_edit_and_export_again(self):
        # Import round, edit it in Blender (tests/edit_round.py: turn a tip bone, lower
        # its stiffness, raise mu_static), export: exactly those three values change.
        path = os.path.join(ROOT, "scenes", "brushes", "round.json")
        blend = os.path.join(TMP, "round-to-edit.blend")
        out = os.path.join(TMP, "round-edited.json")
        rc, _, err = run_blender(["--import", path, "--save", blend])
        self.assertEqual(rc, 0, err)
        cmd = [BLENDER, "-b", "--factory-startup", blend, "--python-exit-code", "1",
               "--python", os.path.join(HERE, "tests", "edit_round.py"), "--python", SCRIPT, "--", out]
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=120)
        self.assertEqual(p.returncode, 0, p.stderr)
        with open(path) as f:
            want = json.load(f)
        want["spines"][0]["rest_angles_rad"][3][0] = 0.1
        want["spines"][0]["stiffness_nmm_per_rad"][3] = 4.0
        want["friction"]["mu_static"] = 0.5
        with open(out) as f:
            got = json.load(f)
        self.assertEqual(differences(got, want), [])
        rc, _, err = run_bristle(["validate", out])
        self.assertEqual(rc, 0, err)

    def test_comparison_can_fail(self):
        # The comparison itself: one changed value beyond its tolerance is reported.
        with open(LIBRARY[0]) as f:
            want = json.load(f)
        got = json.loads(json.dumps(want))
        got["spines"][1]["rest_angles_rad"][2][1] += 3 * ANGLE_TOL_RAD
        got["surface"]["skin"][0][0][1] += 1
        diffs = differences(got, want)
        self.assertEqual(len(diffs), 2, diffs)
        self.assertTrue(diffs[0].startswith("/spines/1/rest_angles_rad/2/1"), diffs)
        # A block the export lost is reported too (the round has hair volume).
        with open(os.path.join(ROOT, "scenes", "brushes", "round.json")) as f:
            round_brush = json.load(f)
        lost = {k: v for k, v in round_brush.items() if k != "volume"}
        diffs = differences(lost, round_brush)
        self.assertTrue(any(d.startswith("/ (keys)") for d in diffs), diffs)
        self.assertTrue(any(d.startswith("/volume") for d in diffs), diffs)


class AddOn(unittest.TestCase):
    def test_menus_and_operators(self):
        rc, out, err = run_blender([os.path.join(ROOT, "scenes", "brushes", "fan.json"), TMP],
                                   script=os.path.join(HERE, "tests", "check_addon.py"))
        self.assertEqual(rc, 0, out[-3000:] + err[-3000:])
        with open(os.path.join(ROOT, "scenes", "brushes", "fan.json")) as f:
            want = json.load(f)
        with open(os.path.join(TMP, "addon-fan.json")) as f:
            got = json.load(f)
        self.assertEqual(differences(got, want), [])


class Skinning(unittest.TestCase):
    def test_blender_deforms_the_cage_as_bristle_skins_it(self):
        # Bent library brushes: Blender's Armature modifier against bristle's skinning
        # formula, vertex by vertex (tests/check_skinning.py holds the tolerance).
        rc, out, err = run_blender(LIBRARY, script=os.path.join(HERE, "tests", "check_skinning.py"))
        self.assertEqual(rc, 0, out[-3000:] + err[-3000:])
        with_surface = []
        for path in LIBRARY:
            with open(path) as f:
                if "surface" in json.load(f):
                    with_surface.append(path)
        self.assertEqual(out.count("largest deviation"), len(with_surface), out)


class BadModels(unittest.TestCase):
    """Exit code 65 and one line naming the object, bone or property."""

    def refused(self, case, *names, args=None):
        out = os.path.join(TMP, case + ".json")
        rc, _, err = run_blender(args if args is not None else [out], blend=fixture(case))
        self.assertEqual(rc, 65, err)
        lines = messages(err)
        self.assertEqual(len(lines), 1, err)
        self.assertTrue(lines[0].startswith("bristle_brush: %s.blend: " % case), lines[0])
        for name in names:
            self.assertIn(name, lines[0])
        self.assertFalse(os.path.exists(out), "no output file after an error")
        return lines[0]

    def test_no_armature(self):
        self.refused("no-armature", "no armature")

    def test_branching_chain(self):
        self.refused("branching", "armature 'handmade'", "bone 'hair0.1'", "'hair0.2b'", "branches")

    def test_cage_without_vertex_groups(self):
        self.refused("no-groups", "cage 'handmade-cage'", "no vertex groups")

    def test_vertex_group_naming_no_bone(self):
        self.refused("stray-group", "cage 'handmade-cage'", "vertex group 'Group'", "names no bone")

    def test_scaled_armature(self):
        self.refused("scaled", "armature 'handmade'", "scale (2, 2, 2)")

    def test_property_out_of_range(self):
        self.refused("bad-friction", "armature 'handmade'", "'mu_static' = 3.0", "[0, 2]")

    def test_misspelt_property(self):
        self.refused("misspelt-prop", "'strips_cont'", "unknown")

    def test_bad_bone_stiffness(self):
        self.refused("bad-stiffness", "bone 'hair1.0'", "'stiffness_nmm_per_rad' = -2")

    def test_polygon_beyond_quads(self):
        self.refused("ngon", "cage 'handmade-cage'", "face 0 has 5 vertices")

    def test_root_above_the_ferrule_mouth(self):
        self.refused("root-above", "bone 'hair0.0'", "z = 1 mm", "z <= 0")

    def test_two_armatures_need_a_choice(self):
        self.refused("two-armatures", "'first'", "'second'", "--armature")
        out = os.path.join(TMP, "second.json")
        rc, _, err = run_blender(["--armature", "second", out], blend=fixture("two-armatures"))
        self.assertEqual(rc, 0, err)
        with open(out) as f:
            self.assertEqual(json.load(f)["name"], "second")


class FixableModels(unittest.TestCase):
    """Exported with a one-line warning per problem; the result is a valid brush."""

    def export(self, case):
        out = os.path.join(TMP, case + ".json")
        rc, _, err = run_blender([out], blend=fixture(case))
        self.assertEqual(rc, 0, err)
        rc2, _, err2 = run_bristle(["validate", out])
        self.assertEqual(rc2, 0, err2)
        with open(out) as f:
            return json.load(f), messages(err)

    def test_unnormalised_weights_are_normalised(self):
        brush, warnings = self.export("unnormalised")
        self.assertEqual(len(warnings), 1, warnings)
        self.assertIn("cage 'handmade-cage'", warnings[0])
        self.assertIn("6 vertices", warnings[0])
        self.assertIn("normalised", warnings[0])
        # The mouth ring was weighted 0.35 / 0.15: normalising gives back the 0.7 / 0.3
        # it was designed with.
        for entries in brush["surface"]["skin"][:6]:
            self.assertEqual(sorted(round(w, 6) for _, _, w in entries), [0.3, 0.7])

    def test_missing_properties_use_defaults(self):
        brush, warnings = self.export("missing-props")
        self.assertEqual(len(warnings), 4, warnings)
        for s in range(3):
            self.assertIn("'hair%d.0', 'hair%d.1', 'hair%d.2'" % (s, s, s), warnings[s])
            self.assertIn("'stiffness_nmm_per_rad'; using 8 N mm/rad", warnings[s])
        self.assertIn("'mu_static'", warnings[3])
        for spine in brush["spines"]:
            self.assertEqual(spine["stiffness_nmm_per_rad"], [8.0, 8.0, 8.0])
        self.assertNotIn("friction", brush)


    def test_armature_modifier_after_subdivision(self):
        brush, warnings = self.export("modifier-order")
        self.assertEqual(len(warnings), 1, warnings)
        self.assertIn("cage 'handmade-cage': the Armature modifier comes after 'Subdivision'", warnings[0])
        self.assertEqual(brush["surface"]["refinement_level"], 2)


    def test_automatic_weights(self):
        # Ctrl+P > Armature Deform > With Automatic Weights: bone-heat weights, which
        # Blender does not normalise, and the Armature modifier after Subdivision.
        brush, warnings = self.export("auto-weights")
        self.assertEqual(len(warnings), 2, warnings)
        self.assertIn("the Armature modifier comes after 'Subdivision'", warnings[0])
        self.assertIn("do not sum to 1", warnings[1])
        skin = brush["surface"]["skin"]
        self.assertEqual(len(skin), len(brush["surface"]["cage_vertices_mm"]))
        for entries in skin:
            # Rounded to 1e-6 each: a list of m weights sums to 1 within m * 5e-7.
            self.assertAlmostEqual(sum(w for _, _, w in entries), 1.0, delta=len(entries) * 5e-7)
        # The mouth ring (vertices 0-5) follows the first bones: point 0.
        for entries in skin[:6]:
            self.assertEqual({p for _, p, _ in entries}, {0})


class CommandLine(unittest.TestCase):
    def test_usage_error(self):
        rc, _, err = run_blender([])
        self.assertEqual(rc, 64, err)
        self.assertIn("nothing to do", messages(err)[0])

    def test_missing_input(self):
        rc, _, err = run_blender(["--import", os.path.join(TMP, "nope.json")])
        self.assertEqual(rc, 66, err)
        self.assertIn("nope.json: no such file", messages(err)[0])

    def test_cannot_create_output(self):
        rc, _, err = run_blender([os.path.join(TMP, "no-such-dir", "x.json")], blend=fixture("handmade"))
        self.assertEqual(rc, 73, err)
        self.assertIn("no-such-dir", messages(err)[0])

    def test_brush_the_importer_cannot_build(self):
        # Well-formed JSON with a skin entry naming spine 9 of a 7-spine brush.
        with open(os.path.join(ROOT, "scenes", "brushes", "round.json")) as f:
            brush = json.load(f)
        brush["surface"]["skin"][3][0][0] = 9
        bad = os.path.join(TMP, "bad-skin.json")
        with open(bad, "w") as f:
            json.dump(brush, f)
        rc, _, err = run_blender(["--import", bad, os.path.join(TMP, "bad-skin-out.json")])
        self.assertEqual(rc, 65, err)
        self.assertEqual(len(messages(err)), 1, err)
        self.assertIn("bad-skin.json: not a valid bristle brush", messages(err)[0])
        self.assertFalse(os.path.exists(os.path.join(TMP, "bad-skin-out.json")))

    def test_malformed_brush(self):
        bad = os.path.join(TMP, "bad.json")
        with open(bad, "w") as f:
            f.write('{"format": "bristle-brush/1", "name": "x", "spines": [}')
        rc, _, err = run_blender(["--import", bad])
        self.assertEqual(rc, 65, err)
        self.assertIn("bad.json: line 1 column", messages(err)[0])


if __name__ == "__main__":
    unittest.main()
