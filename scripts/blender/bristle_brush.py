# bristle brush exporter / importer for Blender 3.4+ (docs/blender.md).
#
# One file, two uses:
#   - a Blender add-on: Edit > Preferences > Add-ons > Install..., then
#     File > Export > bristle brush (.json) and File > Import > bristle brush (.json);
#   - a command-line script, no display needed:
#       blender -b mybrush.blend --python-exit-code 1 --python bristle_brush.py -- mybrush.json
#       blender -b --factory-startup --python-exit-code 1 --python bristle_brush.py -- \
#           --import scenes/brushes/fan.json --save fan.blend
#
# The mapping (Baxter & Lin 2004, §3 spines, §4.1 skinned surface):
#   armature object        -> the brush; its object frame is the brush frame (origin at
#                             the ferrule mouth, hairs along -z); object name -> "name"
#   each chain of bones    -> one spine, from the ferrule mouth to the tip; bone k is
#                             segment k, its rest direction relative to its parent gives
#                             the joint's rest angles (eq. 10), its envelope radii the widths
#   bone custom properties -> stiffness_nmm_per_rad (K, eq. 2), damping_nmm (D, eq. 4)
#   armature object custom properties -> friction, anisotropy, strips, paint, description
#   mesh deformed by the armature     -> the Catmull-Clark cage; vertex groups named
#                             after bones -> skinning weights; Subdivision Surface
#                             modifier levels -> refinement_level
# Blender stores geometry in float32; lengths are rounded to 1e-5 mm and angles to
# 1e-6 rad on export, which removes that noise (see docs/blender.md, "Precision").

bl_info = {
    "name": "bristle brush (.json)",
    "author": "bristle contributors",
    "version": (1, 0, 0),
    "blender": (3, 4, 0),
    "location": "File > Import / Export > bristle brush (.json)",
    "description": "Model a bristle brush (armature spines + skinned cage) and export it "
                   "as a bristle-brush/1 file, or import one",
    "category": "Import-Export",
}

import json
import math
import os
import re
import sys
import tempfile

import bpy

FORMAT = "bristle-brush/1"

# Limits of the brush format (docs/brush-format.md, engine/model/brush.h).
MAX_SPINES = 64
MAX_JOINTS_PER_SPINE = 16
MAX_CAGE_VERTICES = 4096
MAX_REST_ANGLE_RAD = 1.2
MAX_REFINEMENT_LEVEL = 4
SKIN_WEIGHT_SUM_TOL = 1e-3  # kSkinWeightSumTol: bristle's own tolerance on a weight sum

# Rounding of exported values. Blender keeps coordinates in float32 (24-bit mantissa):
# at 60 mm from the origin one unit in the last place is 3.8e-6 mm, and a direction
# computed from two such points over a >= 2 mm segment is off by <= ~2e-6 rad.
LENGTH_DECIMALS = 5   # mm: 1e-5 mm = 10 nm, far below a 125 um pixel at 8 px/mm
ANGLE_DECIMALS = 6    # rad: keeps a straight joint exactly 0
WEIGHT_DECIMALS = 6   # a float32 weight such as 0.7 (0.69999999) comes back as 0.7

# Used, with a warning, when a bone has no stiffness: the middle of the paper's
# §5 calibration range of 5-10 N mm/rad (docs/brush-format.md §4).
DEFAULT_STIFFNESS_NMM_PER_RAD = 8.0
# Used, with a warning, when the cage has no Subdivision Surface modifier (bristle's default).
DEFAULT_REFINEMENT_LEVEL = 2

# Exit codes of the command-line form (the same as bristle's, README.md).
EXIT_USAGE, EXIT_DATA, EXIT_NO_INPUT, EXIT_CANT_CREATE, EXIT_IO = 64, 65, 66, 73, 74

BONE_STIFFNESS = "stiffness_nmm_per_rad"
BONE_DAMPING = "damping_nmm"
# A slab of a flat's row (docs/brush-format.md, "Slabs"): its thickness at the
# bone's tail, and on a chain's first bone also at its head (the spine's root).
BONE_THICKNESS = "thickness_mm"
BONE_ROOT_THICKNESS = "root_thickness_mm"
BONE_FLAT_LOAD = "flat_load_n"

# Brush-object custom properties: name -> (JSON place, type, check, rule text).
# Ranges are the reader's rules (docs/brush-format.md §3), so a bad value is named
# here, in Blender terms, instead of by `bristle validate` later.
OBJECT_PROPS = {
    "description": (str, None, ""),
    "mu_static": (float, lambda v: 0 <= v <= 2, "in [0, 2]"),
    "mu_kinetic": (float, lambda v: 0 <= v <= 2, "in [0, 2]"),
    "anisotropy_strength": (float, lambda v: 0 <= v <= 1, "in [0, 1]"),
    "anisotropy_exponent": (float, lambda v: v >= 1, ">= 1"),
    "strips_count": (int, lambda v: 1 <= v <= 1000, "in 1..1000"),
    "strips_root_width_mm": (float, lambda v: 0 < v <= 5, "in (0, 5]"),
    "strips_tip_width_mm": (float, lambda v: v >= 0, ">= 0"),
    "strips_seed": (int, lambda v: v >= 0, ">= 0"),
    "strips_placement": (str, lambda v: v in ("auto", "line", "area"), "auto, line or area"),
    "strips_length_jitter": (float, lambda v: 0 <= v < 1, "in [0, 1)"),
    "strips_clumps": (int, lambda v: v >= 0, ">= 0"),
    "strips_clumping": (float, lambda v: 0 <= v <= 1, "in [0, 1]"),
    "paint_capacity": (float, lambda v: v > 0, "> 0"),
    "paint_flag_mm": (float, lambda v: 0 <= v <= 5, "in [0, 5]"),
    "paint_wicking": (float, lambda v: 0 <= v <= 1, "in [0, 1]"),
    # Hair volume (docs/brush-format.md): the ranges bristle's reader enforces.
    "volume_min_separation": (float, lambda v: 0 < v < 1, "in (0, 1)"),
    "volume_stiffness_n_per_mm": (float, lambda v: 0 < v <= 1000, "in (0, 1000]"),
    "volume_max_separation": (float, lambda v: 1 < v <= 100, "in (1, 100]"),
    "volume_cohesion_n_per_mm": (float, lambda v: 0 < v <= 1000, "in (0, 1000]"),
    "volume_tip_spread": (float, lambda v: 0 <= v <= 1, "in [0, 1]"),
    "volume_spread_n_per_mm": (float, lambda v: 0 <= v <= 1000, "in [0, 1000]"),
    "volume_squash_after_mm": (float, lambda v: 0 <= v <= 100, "in [0, 100]"),
    "volume_spread_ramp": (float, lambda v: 0 <= v <= 10, "in [0, 10]"),
    "solver_friction_form": (str, lambda v: v in ("auto", "epigraph", "objective"),
                             "auto, epigraph or objective"),
}
OBJECT_PROP_PREFIXES = ("mu_", "anisotropy_", "strips_", "paint_", "volume_", "solver_")
# The volume block's keys after volume_, in the library files' order.
VOLUME_KEYS = ("min_separation", "stiffness_n_per_mm", "max_separation", "cohesion_n_per_mm",
               "tip_spread", "spread_n_per_mm", "squash_after_mm", "spread_ramp")


class BrushError(Exception):
    """A problem with the brush being exported or imported: one line, naming the
    object, bone or property, and the exit code of the command-line form."""

    def __init__(self, message, code=EXIT_DATA):
        super().__init__(message)
        self.code = code


# ---------------------------------------------------------------------------
# Small double-precision 3D helpers. mathutils works in float32, so the angle
# computations use plain Python floats (doubles) instead.

def _sub(a, b):
    return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]


def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _norm(a):
    return math.sqrt(_dot(a, a))


def _matvec(m, v):
    return [_dot(m[0], v), _dot(m[1], v), _dot(m[2], v)]


def _matmul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def _transpose(m):
    return [[m[j][i] for j in range(3)] for i in range(3)]


def _joint_rotation(theta, phi):
    """R = Ry(phi) Rx(theta), the joint rotation of eq. 10 (docs/brush-format.md §1)."""
    ct, st, cp, sp = math.cos(theta), math.sin(theta), math.cos(phi), math.sin(phi)
    rx = [[1, 0, 0], [0, ct, -st], [0, st, ct]]
    ry = [[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]]
    return _matmul(ry, rx)


def _joint_angles(local_dir):
    """The (theta, phi) that turn -z onto the unit vector local_dir, given in the
    parent segment's frame. Ry(phi) Rx(theta) (0, 0, -1) =
    (-sin(phi) cos(theta), sin(theta), -cos(phi) cos(theta)), and |theta| < pi/2."""
    ux, uy, uz = local_dir
    theta = math.asin(max(-1.0, min(1.0, uy)))
    phi = math.atan2(-ux, -uz)
    return theta, phi


def spine_points(root, lengths, angles):
    """Rest points 0..n of a spine: frame F_k = F_(k-1) Ry(phi_k) Rx(theta_k) with
    F_(-1) the ferrule (identity); segment k runs along F_k (0, 0, -1)."""
    frame = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
    points = [list(root)]
    for length, (theta, phi) in zip(lengths, angles):
        frame = _matmul(frame, _joint_rotation(theta, phi))
        d = _matvec(frame, [0.0, 0.0, -1.0])
        p = points[-1]
        points.append([p[0] + length * d[0], p[1] + length * d[1], p[2] + length * d[2]])
    return points


def spine_angles(points):
    """Inverse of spine_points: segment lengths and (theta, phi) per joint."""
    frame = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
    lengths, angles = [], []
    for a, b in zip(points, points[1:]):
        seg = _sub(b, a)
        length = _norm(seg)
        local = _matvec(_transpose(frame), [c / length for c in seg])
        theta, phi = _joint_angles(local)
        frame = _matmul(frame, _joint_rotation(theta, phi))
        lengths.append(length)
        angles.append((theta, phi))
    return lengths, angles


def _round(x, decimals):
    r = round(float(x), decimals)
    return 0.0 if r == 0 else r  # no "-0.0" in the file


def _natural_key(name):
    return [int(t) if t.isdigit() else t for t in re.split(r"(\d+)", name)]


# ---------------------------------------------------------------------------
# Export: Blender scene -> brush dictionary

class _Export:
    def __init__(self, scene, arm_obj, warn):
        self.scene = scene
        self.arm = arm_obj
        self.warn = warn
        self.where = "armature '%s'" % arm_obj.name
        units = scene.unit_settings
        if units.scale_length <= 0:
            raise BrushError("scene '%s': unit scale %g must be > 0" % (scene.name, units.scale_length))
        # One Blender unit is scale_length metres (Scene > Units > Unit Scale).
        self.mm_per_unit = units.scale_length * 1000.0

    def mm(self, value_bu):
        return float(value_bu) * self.mm_per_unit

    def check_scale(self):
        scale = self.arm.matrix_world.to_scale()
        if any(abs(s - 1.0) > 1e-5 for s in scale):
            raise BrushError("%s: object scale (%.6g, %.6g, %.6g) is not 1: apply it "
                             "(Object > Apply > Scale) so bone lengths are true lengths"
                             % (self.where, scale[0], scale[1], scale[2]))

    def bone_chains(self):
        bones = self.arm.data.bones
        if len(bones) == 0:
            raise BrushError("%s: has no bones; each chain of bones is one spine" % self.where)
        roots = sorted((b for b in bones if b.parent is None), key=lambda b: _natural_key(b.name))
        chains = []
        for root in roots:
            chain = [root]
            while chain[-1].children:
                kids = chain[-1].children
                if len(kids) > 1:
                    raise BrushError("%s: bone '%s' branches into %s: a spine is one unbranched "
                                     "chain of bones from the ferrule to the tip"
                                     % (self.where, chain[-1].name,
                                        ", ".join("'%s'" % k.name for k in kids)))
                chain.append(kids[0])
            if len(chain) > MAX_JOINTS_PER_SPINE:
                raise BrushError("%s: the chain from bone '%s' has %d bones; a spine has at most %d"
                                 % (self.where, root.name, len(chain), MAX_JOINTS_PER_SPINE))
            chains.append(chain)
        if len(chains) > MAX_SPINES:
            raise BrushError("%s: %d bone chains; a brush has at most %d spines"
                             % (self.where, len(chains), MAX_SPINES))
        return chains

    def bone_prop(self, bone, key):
        """A bone's custom property: the Bone (edit/object mode panel) first, then
        the PoseBone (pose mode panel)."""
        if key in bone.keys():
            return bone[key]
        pose_bone = self.arm.pose.bones.get(bone.name) if self.arm.pose else None
        if pose_bone is not None and key in pose_bone.keys():
            return pose_bone[key]
        return None

    def bone_number(self, bone, key, default, check, rule):
        value = self.bone_prop(bone, key)
        if value is None:
            return default
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise BrushError("%s: bone '%s': custom property '%s' = %r must be a number"
                             % (self.where, bone.name, key, value))
        value = float(value)
        if not math.isfinite(value) or not check(value):
            raise BrushError("%s: bone '%s': custom property '%s' = %g must be %s"
                             % (self.where, bone.name, key, value, rule))
        return value

    def spine(self, chain):
        # Rest pose, armature space: head_local / tail_local ignore any pose.
        points = [[self.mm(c) for c in chain[0].head_local]]
        for k, bone in enumerate(chain):
            if k > 0:
                gap = _norm(_sub([self.mm(c) for c in bone.head_local], points[-1]))
                if gap > 10 ** -(LENGTH_DECIMALS - 1):
                    raise BrushError("%s: bone '%s' starts %.4g mm away from the tail of its "
                                     "parent '%s'; connect it (a spine's segments are contiguous)"
                                     % (self.where, bone.name, gap, chain[k - 1].name))
            points.append([self.mm(c) for c in bone.tail_local])
        root = [_round(c, LENGTH_DECIMALS) for c in points[0]]
        if root[2] > 0:
            raise BrushError("%s: bone '%s' starts at z = %.4g mm, above the ferrule mouth (the "
                             "armature's origin); a spine's root must have z <= 0"
                             % (self.where, chain[0].name, root[2]))
        lengths, angles = spine_angles(points)
        for bone, (theta, phi) in zip(chain, angles):
            if abs(theta) > MAX_REST_ANGLE_RAD or abs(phi) > MAX_REST_ANGLE_RAD:
                raise BrushError("%s: bone '%s' turns by (theta %.3f, phi %.3f) rad from its parent "
                                 "(or from -z); each rest angle must be within +-%.1f rad"
                                 % (self.where, bone.name, theta, phi, MAX_REST_ANGLE_RAD))
        # Widths: envelope diameters. Point 0 is the first bone's head, point k + 1
        # bone k's tail (a connected child's head radius is its parent's tail radius).
        radii = [chain[0].head_radius] + [b.tail_radius for b in chain]
        widths = [_round(2 * self.mm(r), LENGTH_DECIMALS) for r in radii]
        if widths[0] <= 0:
            raise BrushError("%s: bone '%s': head radius 0 gives the root no width; set the "
                             "envelope head radius (the root's half width)" % (self.where, chain[0].name))
        stiffness, damping, missing = [], [], []
        for bone in chain:
            k = self.bone_number(bone, BONE_STIFFNESS, None, lambda v: v > 0, "> 0 (N mm/rad)")
            if k is None:
                missing.append(bone.name)
                k = DEFAULT_STIFFNESS_NMM_PER_RAD
            stiffness.append(k)
            damping.append(self.bone_number(bone, BONE_DAMPING, 0.0, lambda v: v >= 0, ">= 0 (N mm)"))
        if missing:
            self.warn("%s: bone%s %s: no custom property '%s'; using %g N mm/rad"
                      % (self.where, "s" if len(missing) > 1 else "",
                         ", ".join("'%s'" % n for n in missing), BONE_STIFFNESS,
                         DEFAULT_STIFFNESS_NMM_PER_RAD))
        spine = {
            "root_mm": root,
            "segment_lengths_mm": [_round(x, LENGTH_DECIMALS) for x in lengths],
            "stiffness_nmm_per_rad": stiffness,
            "damping_nmm": damping,
            "rest_angles_rad": [[_round(t, ANGLE_DECIMALS), _round(p, ANGLE_DECIMALS)]
                                for t, p in angles],
            "width_mm": widths,
        }
        # A slab: all of its thicknesses, or none (a round bundle).
        tails = [self.bone_number(b, BONE_THICKNESS, None, lambda v: v >= 0, ">= 0 (mm)")
                 for b in chain]
        head = self.bone_number(chain[0], BONE_ROOT_THICKNESS, None, lambda v: v > 0, "> 0 (mm)")
        given = [t is not None for t in tails] + [head is not None]
        if any(given):
            if not all(given):
                raise BrushError("%s: bone chain from '%s': a slab needs '%s' on its first bone and "
                                 "'%s' on every bone; some are missing"
                                 % (self.where, chain[0].name, BONE_ROOT_THICKNESS, BONE_THICKNESS))
            spine["thickness_mm"] = [_round(t, LENGTH_DECIMALS) for t in [head] + tails]
        # The load that presses the bundle flat: on the chain's first bone.
        flat = self.bone_number(chain[0], BONE_FLAT_LOAD, None, lambda v: 0 < v <= 1, "in (0, 1] (N)")
        if flat is not None:
            spine["flat_load_n"] = flat
        return spine, points

    def find_cage(self):
        cages = []
        for obj in self.scene.objects:
            if obj.type != 'MESH':
                continue
            driven = any(m.type == 'ARMATURE' and m.object == self.arm for m in obj.modifiers)
            if driven or obj.parent == self.arm:
                cages.append(obj)
        if len(cages) > 1:
            raise BrushError("%s: %d meshes follow it (%s); a brush has one cage"
                             % (self.where, len(cages), ", ".join("'%s'" % c.name for c in cages)))
        return cages[0] if cages else None

    def surface(self, cage, chains, spine_points_mm):
        where = "cage '%s'" % cage.name
        mesh = cage.data  # the un-deformed, un-subdivided cage: no evaluated mesh
        if len(mesh.vertices) == 0:
            raise BrushError("%s: has no vertices" % where)
        if len(mesh.vertices) > MAX_CAGE_VERTICES:
            raise BrushError("%s: %d vertices; a cage has at most %d"
                             % (where, len(mesh.vertices), MAX_CAGE_VERTICES))
        if len(mesh.polygons) == 0:
            raise BrushError("%s: has no faces" % where)
        faces = []
        for poly in mesh.polygons:
            if len(poly.vertices) not in (3, 4):
                raise BrushError("%s: face %d has %d vertices; the cage takes triangles and quads"
                                 % (where, poly.index, len(poly.vertices)))
            faces.append([int(v) for v in poly.vertices])
        if not cage.vertex_groups:
            raise BrushError("%s: has no vertex groups; name one after each bone it follows "
                             "(e.g. Ctrl+P > Armature Deform > With Automatic Weights)" % where)
        bone_of = {}
        for s, chain in enumerate(chains):
            for k, bone in enumerate(chain):
                bone_of[bone.name] = (s, k)
        for group in cage.vertex_groups:
            if group.name not in bone_of:
                raise BrushError("%s: vertex group '%s' names no bone of %s; rename or delete it"
                                 % (where, group.name, self.where))
        modifiers = list(cage.modifiers)
        kinds = [m.type for m in modifiers]
        subsurf = next((m for m in modifiers if m.type == 'SUBSURF'), None)
        if subsurf is None:
            level = DEFAULT_REFINEMENT_LEVEL
            self.warn("%s: no Subdivision Surface modifier; refinement_level %d" % (where, level))
        else:
            level = subsurf.levels
            if level > MAX_REFINEMENT_LEVEL:
                raise BrushError("%s: modifier '%s': levels %d; refinement_level is at most %d"
                                 % (where, subsurf.name, level, MAX_REFINEMENT_LEVEL))
            if 'ARMATURE' in kinds and kinds.index('ARMATURE') > kinds.index('SUBSURF'):
                self.warn("%s: the Armature modifier comes after '%s', so Blender deforms the "
                          "subdivided mesh; bristle skins the cage, then subdivides (move it up)"
                          % (where, subsurf.name))

        # Cage vertices into the brush (armature) frame, in double precision.
        to_arm = self.arm.matrix_world.inverted() @ cage.matrix_world
        m = [[float(to_arm[i][j]) for j in range(4)] for i in range(4)]
        vertices, skin, unnormalised = [], [], []
        for v in mesh.vertices:
            co = [float(c) for c in v.co]
            p = [self.mm(sum(m[i][j] * co[j] for j in range(3)) + m[i][3]) for i in range(3)]
            vertices.append([_round(c, LENGTH_DECIMALS) for c in p])
            weights = {}
            for g in v.groups:
                if g.weight <= 0:
                    continue
                s, k = bone_of[cage.vertex_groups[g.group].name]
                n = len(chains[s])
                point = k
                if k == n - 1:
                    # Bone n-1 carries both its head (point n-1) and the tip (point n):
                    # bristle moves both rigidly with the last segment (brush-format.md,
                    # "Skinning"), so either is exact. Name the nearer one, as a hand-made
                    # or generated (tube_cage) cage does.
                    a, b = spine_points_mm[s][k], spine_points_mm[s][k + 1]
                    axis = _sub(b, a)
                    if _dot(_sub(p, a), axis) > 0.5 * _dot(axis, axis):
                        point = n
                weights[(s, point)] = weights.get((s, point), 0.0) + float(g.weight)
            total = sum(weights.values())
            if total <= 0:
                raise BrushError("%s: vertex %d has no weight in any bone's vertex group; every "
                                 "cage vertex must follow a spine" % (where, v.index))
            if abs(total - 1.0) > SKIN_WEIGHT_SUM_TOL:
                unnormalised.append((v.index, total))
            entries = [[s, pt, _round(w / total, WEIGHT_DECIMALS)]
                       for (s, pt), w in sorted(weights.items()) if w / total >= 0.5e-6]
            skin.append(entries)
        if unnormalised:
            first, total = unnormalised[0]
            self.warn("%s: the weights of %d vertices do not sum to 1 (vertex %d: %.4g); "
                      "normalised, as Blender's Armature modifier does"
                      % (where, len(unnormalised), first, total))
        return {"cage_vertices_mm": vertices, "faces": faces, "skin": skin,
                "refinement_level": int(level)}

    def object_props(self):
        props = {}
        for key in self.arm.keys():
            if key in OBJECT_PROPS:
                kind, check, rule = OBJECT_PROPS[key]
                value = self.arm[key]
                ok_type = (isinstance(value, str) if kind is str else
                           isinstance(value, (int, float)) and not isinstance(value, bool))
                if kind is not str and ok_type and not math.isfinite(value):
                    ok_type = False  # JSON has no NaN or infinity
                if kind is int and ok_type and float(value) != int(value):
                    ok_type = False
                if not ok_type:
                    raise BrushError("%s: custom property '%s' = %r must be %s"
                                     % (self.where, key, value,
                                        {str: "a string", int: "a whole number",
                                         float: "a finite number"}[kind]))
                value = kind(value)
                if check is not None and not check(value):
                    raise BrushError("%s: custom property '%s' = %r must be %s"
                                     % (self.where, key, value, rule))
                props[key] = value
            elif key.startswith(OBJECT_PROP_PREFIXES):
                raise BrushError("%s: unknown custom property '%s' (known: %s)"
                                 % (self.where, key, ", ".join(sorted(OBJECT_PROPS))))
        return props

    def brush(self):
        self.check_scale()
        chains = self.bone_chains()
        spines, points = [], []
        for chain in chains:
            spine, pts = self.spine(chain)
            spines.append(spine)
            points.append(pts)
        props = self.object_props()
        out = {"format": FORMAT, "name": self.arm.name}
        if props.get("description"):
            out["description"] = props["description"]
        out["spines"] = spines

        if "mu_static" in props:
            friction = {"mu_static": props["mu_static"]}
            if "mu_kinetic" in props:
                if props["mu_kinetic"] > props["mu_static"]:
                    raise BrushError("%s: custom property 'mu_kinetic' = %g must be <= mu_static (%g)"
                                     % (self.where, props["mu_kinetic"], props["mu_static"]))
                friction["mu_kinetic"] = props["mu_kinetic"]
            if "anisotropy_strength" in props:
                friction["anisotropy"] = {"strength": props["anisotropy_strength"]}
                if "anisotropy_exponent" in props:
                    friction["anisotropy"]["exponent"] = props["anisotropy_exponent"]
            elif "anisotropy_exponent" in props:
                self.warn("%s: 'anisotropy_exponent' without 'anisotropy_strength': isotropic "
                          "friction (strength 0)" % self.where)
            out["friction"] = friction
        else:
            ignored = [k for k in ("mu_kinetic", "anisotropy_strength", "anisotropy_exponent")
                       if k in props]
            self.warn("%s: no custom property 'mu_static': bristle's default friction "
                      "(mu 0.4 / 0.35, isotropic)%s" % (self.where,
                      "; ignores " + ", ".join(ignored) if ignored else ""))

        cage = self.find_cage()
        if cage is not None:
            out["surface"] = self.surface(cage, chains, points)

        strip_keys = {"strips_root_width_mm": "root_width_mm", "strips_tip_width_mm": "tip_width_mm",
                      "strips_seed": "seed", "strips_placement": "placement",
                      "strips_length_jitter": "length_jitter", "strips_clumps": "clumps",
                      "strips_clumping": "clumping"}
        if "strips_count" in props:
            strips = {"count": props["strips_count"]}
            for key, name in strip_keys.items():
                if key in props:
                    strips[name] = props[key]
            out["strips"] = strips
        elif any(k in props for k in strip_keys):
            self.warn("%s: strips_* properties without 'strips_count': no strips" % self.where)
        if "volume_min_separation" in props:
            out["volume"] = {k: props["volume_" + k] for k in VOLUME_KEYS if "volume_" + k in props}
        elif any("volume_" + k in props for k in VOLUME_KEYS):
            self.warn("%s: volume_* properties without 'volume_min_separation': no hair volume"
                      % self.where)
        paint = {name: props["paint_" + name] for name in ("capacity", "flag_mm", "wicking")
                 if "paint_" + name in props}
        if paint:
            out["paint"] = paint
        if "solver_friction_form" in props:
            out["solver"] = {"friction_form": props["solver_friction_form"]}
        return out


def find_armature(scene, name=None):
    """The brush to export: the named armature, else the only armature, else the
    active object if it is an armature."""
    arms = [o for o in scene.objects if o.type == 'ARMATURE']
    if name is not None:
        for o in arms:
            if o.name == name:
                return o
        raise BrushError("scene '%s': no armature named '%s' (armatures: %s)"
                         % (scene.name, name, ", ".join("'%s'" % o.name for o in arms) or "none"))
    if not arms:
        raise BrushError("scene '%s': no armature; a brush is an armature whose bone chains "
                         "are its spines" % scene.name)
    if len(arms) == 1:
        return arms[0]
    active = bpy.context.view_layer.objects.active if bpy.context.view_layer else None
    if active is not None and active.type == 'ARMATURE':
        return active
    raise BrushError("scene '%s': %d armatures (%s); choose one (--armature NAME, or make it active)"
                     % (scene.name, len(arms), ", ".join("'%s'" % o.name for o in arms)))


def export_brush(scene, arm_obj, warn):
    """The brush dictionary (bristle-brush/1) of an armature and its cage."""
    return _Export(scene, arm_obj, warn).brush()


def _depth(value):
    return 1 + max((_depth(x) for x in value), default=0) if isinstance(value, list) else 0


def _format_json(value, indent=0):
    """JSON laid out like scenes/brushes/*.json: objects one key a line; a list of
    numbers, a short list of number pairs or triples, and each vertex's skin list
    on one line; longer lists one element a line."""
    pad = "  " * indent
    if isinstance(value, dict):
        items = ['%s  %s: %s' % (pad, json.dumps(k), _format_json(v, indent + 1))
                 for k, v in value.items()]
        return "{\n" + ",\n".join(items) + "\n" + pad + "}"
    if isinstance(value, list):
        depth = _depth(value)
        one_line = not any(isinstance(x, dict) for x in value) and (
            depth <= 1 or (depth == 2 and len(value) <= 16) or (depth == 3 and indent >= 3))
        if one_line:
            return json.dumps(value, separators=(", ", ": "))
        return "[\n" + ",\n".join(pad + "  " + _format_json(x, indent + 1) for x in value) + \
            "\n" + pad + "]"
    return json.dumps(value)


def write_brush_file(path, brush):
    """Write atomically: a temporary file next to the target, renamed over it, so
    a failure never leaves a partial file."""
    directory = os.path.dirname(os.path.abspath(path))
    try:
        fd, tmp = tempfile.mkstemp(prefix=".bristle-brush-", suffix=".tmp", dir=directory)
    except OSError as e:
        raise BrushError("%s: cannot create: %s" % (path, e.strerror), EXIT_CANT_CREATE)
    try:
        with os.fdopen(fd, "w") as f:
            f.write(_format_json(brush) + "\n")
        os.replace(tmp, path)
    except OSError as e:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise BrushError("%s: cannot write: %s" % (path, e.strerror), EXIT_IO)


# ---------------------------------------------------------------------------
# Import: brush file -> armature, bones, cage

def _need(obj, key, pointer, path):
    if not isinstance(obj, dict) or key not in obj:
        raise BrushError("%s: %s: missing '%s'" % (path, pointer or "/", key))
    return obj[key]


def read_brush_file(path):
    try:
        with open(path) as f:
            text = f.read()
    except FileNotFoundError:
        raise BrushError("%s: no such file" % path, EXIT_NO_INPUT)
    except OSError as e:
        raise BrushError("%s: cannot read: %s" % (path, e.strerror), EXIT_IO)
    try:
        brush = json.loads(text)
    except json.JSONDecodeError as e:
        raise BrushError("%s: line %d column %d: malformed JSON: %s" % (path, e.lineno, e.colno, e.msg))
    if _need(brush, "format", "", path) != FORMAT:
        raise BrushError("%s: /format = %s: must be \"%s\"" % (path, json.dumps(brush["format"]), FORMAT))
    spines = _need(brush, "spines", "", path)
    if not isinstance(spines, list) or not spines:
        raise BrushError("%s: /spines: must be a non-empty array" % path)
    for i, s in enumerate(spines):
        for key in ("root_mm", "segment_lengths_mm", "stiffness_nmm_per_rad", "width_mm"):
            _need(s, key, "/spines/%d" % i, path)
        n = len(s["segment_lengths_mm"])
        if len(s["width_mm"]) != n + 1:
            raise BrushError("%s: /spines/%d/width_mm: needs n + 1 = %d widths" % (path, i, n + 1))
    return brush


def import_brush_file(context, path, set_units=True):
    """read_brush_file + import_brush. The reader checks the structure the importer
    relies on first; whatever else is wrong with the file (an index out of range, a
    number that is a string, ...) is reported in one line too: `bristle validate`
    then names the exact field."""
    brush = read_brush_file(path)
    before = set(bpy.data.objects)
    try:
        return import_brush(context, brush, set_units)
    except (KeyError, IndexError, TypeError, ValueError) as e:
        # Leave the scene as it was: no half-built brush.
        active = context.view_layer.objects.active
        if active is not None and active.mode != 'OBJECT':
            bpy.ops.object.mode_set(mode='OBJECT')
        for obj in set(bpy.data.objects) - before:
            bpy.data.objects.remove(obj)
        raise BrushError("%s: not a valid bristle brush (%s: %s); `bristle validate %s` names "
                         "the field" % (path, type(e).__name__, e, os.path.basename(path)))


def bone_name(spine, segment):
    return "spine%d.%d" % (spine, segment)


def import_brush(context, brush, set_units=True):
    """Build the brush in the current scene: an armature (one bone chain per spine,
    rest angles from eq. 10, envelope radii = half widths, K and D as bone custom
    properties), brush-level custom properties, and the cage with vertex groups.
    Returns the armature object."""
    scene = context.scene
    units = scene.unit_settings
    if set_units:
        # One Blender unit = one millimetre: brush-sized numbers in the UI.
        units.system = 'METRIC'
        units.scale_length = 0.001
        units.length_unit = 'MILLIMETERS'
    bu_per_mm = 1.0 / (units.scale_length * 1000.0)

    active = context.view_layer.objects.active
    if active is not None and active.mode != 'OBJECT':
        bpy.ops.object.mode_set(mode='OBJECT')
    name = brush["name"]
    arm_data = bpy.data.armatures.new(name)
    arm_data.display_type = 'ENVELOPE'
    arm = bpy.data.objects.new(name, arm_data)
    context.collection.objects.link(arm)
    for o in context.view_layer.objects:
        o.select_set(False)
    arm.select_set(True)
    context.view_layer.objects.active = arm

    chains = []  # per spine: bone names
    bpy.ops.object.mode_set(mode='EDIT')
    for s, spine in enumerate(brush["spines"]):
        n = len(spine["segment_lengths_mm"])
        angles = spine.get("rest_angles_rad", [[0.0, 0.0]] * n)
        points = spine_points(spine["root_mm"], spine["segment_lengths_mm"], angles)
        widths = spine["width_mm"]
        names, parent = [], None
        for k in range(n):
            eb = arm_data.edit_bones.new(bone_name(s, k))
            eb.head = [c * bu_per_mm for c in points[k]]
            eb.tail = [c * bu_per_mm for c in points[k + 1]]
            eb.roll = 0.0
            eb.head_radius = 0.5 * widths[k] * bu_per_mm
            eb.tail_radius = 0.5 * widths[k + 1] * bu_per_mm
            if parent is not None:
                eb.parent = parent
                eb.use_connect = True
            parent = eb
            names.append(eb.name)
        chains.append(names)
    bpy.ops.object.mode_set(mode='OBJECT')

    for s, spine in enumerate(brush["spines"]):
        for k, bname in enumerate(chains[s]):
            bone = arm_data.bones[bname]
            bone[BONE_STIFFNESS] = float(spine["stiffness_nmm_per_rad"][k])
            if "damping_nmm" in spine:
                bone[BONE_DAMPING] = float(spine["damping_nmm"][k])
            if "thickness_mm" in spine:
                bone[BONE_THICKNESS] = float(spine["thickness_mm"][k + 1])
                if k == 0:
                    bone[BONE_ROOT_THICKNESS] = float(spine["thickness_mm"][0])
            if k == 0 and "flat_load_n" in spine:
                bone[BONE_FLAT_LOAD] = float(spine["flat_load_n"])

    if brush.get("description"):
        arm["description"] = brush["description"]
    friction = brush.get("friction")
    if friction is not None:
        arm["mu_static"] = float(friction["mu_static"])
        if "mu_kinetic" in friction:
            arm["mu_kinetic"] = float(friction["mu_kinetic"])
        aniso = friction.get("anisotropy")
        if aniso is not None:
            arm["anisotropy_strength"] = float(aniso["strength"])
            if "exponent" in aniso:
                arm["anisotropy_exponent"] = float(aniso["exponent"])
    strips = brush.get("strips")
    if strips is not None:
        arm["strips_count"] = int(strips["count"])
        for key, kind in (("root_width_mm", float), ("tip_width_mm", float), ("seed", int),
                          ("placement", str), ("length_jitter", float), ("clumps", int),
                          ("clumping", float)):
            if key in strips:
                arm["strips_" + key] = kind(strips[key])
    volume = brush.get("volume")
    if volume is not None:
        for key in VOLUME_KEYS:
            if key in volume:
                arm["volume_" + key] = float(volume[key])
    paint = brush.get("paint")
    if paint is not None:
        for key in ("capacity", "flag_mm", "wicking"):
            if key in paint:
                arm["paint_" + key] = float(paint[key])
    solver = brush.get("solver")
    if solver is not None and "friction_form" in solver:
        arm["solver_friction_form"] = str(solver["friction_form"])

    surface = brush.get("surface")
    if surface is not None:
        mesh = bpy.data.meshes.new(name + ".cage")
        verts = [[c * bu_per_mm for c in v] for v in surface["cage_vertices_mm"]]
        mesh.from_pydata(verts, [], [list(f) for f in surface["faces"]])
        mesh.update()
        for poly in mesh.polygons:
            poly.use_smooth = True
        cage = bpy.data.objects.new(name + ".cage", mesh)
        context.collection.objects.link(cage)
        cage.parent = arm
        groups = {}
        for s, names in enumerate(chains):
            for k, bname in enumerate(names):
                groups[(s, k)] = cage.vertex_groups.new(name=bname)
        for vi, entries in enumerate(surface["skin"]):
            for s, point, weight in entries:
                n = len(chains[s])
                # The tip (point n) moves rigidly with the last segment: bone n-1.
                groups[(s, min(point, n - 1))].add([vi], float(weight), 'ADD')
        # bristle skins the cage, then subdivides: Armature first, then Subdivision
        # Surface with OpenSubdiv's EDGE_AND_CORNER boundary rule (= "Keep Corners").
        mod = cage.modifiers.new("Armature", 'ARMATURE')
        mod.object = arm
        mod.use_vertex_groups = True
        mod.use_bone_envelopes = False
        sub = cage.modifiers.new("Subdivision", 'SUBSURF')
        level = int(surface.get("refinement_level", DEFAULT_REFINEMENT_LEVEL))
        sub.levels = level
        sub.render_levels = level
        sub.boundary_smooth = 'PRESERVE_CORNERS'
    return arm


# ---------------------------------------------------------------------------
# Add-on: operators and File menu entries

from bpy_extras.io_utils import ExportHelper, ImportHelper  # noqa: E402


class EXPORT_SCENE_OT_bristle_brush(bpy.types.Operator, ExportHelper):
    """Export the armature and its cage as a bristle brush (bristle-brush/1 JSON)"""
    bl_idname = "export_scene.bristle_brush"
    bl_label = "Export bristle brush"
    filename_ext = ".json"
    filter_glob: bpy.props.StringProperty(default="*.json", options={'HIDDEN'})
    armature: bpy.props.StringProperty(
        name="Armature", description="Armature to export (empty: the only or the active one)")

    def execute(self, context):
        warnings = []
        try:
            arm = find_armature(context.scene, self.armature or None)
            brush = export_brush(context.scene, arm, warnings.append)
            write_brush_file(self.filepath, brush)
        except BrushError as e:
            self.report({'ERROR'}, str(e))
            return {'CANCELLED'}
        for w in warnings:
            self.report({'WARNING'}, w)
        self.report({'INFO'}, "bristle brush '%s' written to %s" % (brush["name"], self.filepath))
        return {'FINISHED'}


class IMPORT_SCENE_OT_bristle_brush(bpy.types.Operator, ImportHelper):
    """Import a bristle brush (bristle-brush/1 JSON) as an armature and its cage"""
    bl_idname = "import_scene.bristle_brush"
    bl_label = "Import bristle brush"
    filename_ext = ".json"
    filter_glob: bpy.props.StringProperty(default="*.json", options={'HIDDEN'})
    set_units: bpy.props.BoolProperty(
        name="Millimetre units", default=True,
        description="Set the scene's unit scale so that one Blender unit is one millimetre")

    def execute(self, context):
        try:
            import_brush_file(context, self.filepath, self.set_units)
        except BrushError as e:
            self.report({'ERROR'}, str(e))
            return {'CANCELLED'}
        return {'FINISHED'}


def _menu_export(self, context):
    self.layout.operator(EXPORT_SCENE_OT_bristle_brush.bl_idname, text="bristle brush (.json)")


def _menu_import(self, context):
    self.layout.operator(IMPORT_SCENE_OT_bristle_brush.bl_idname, text="bristle brush (.json)")


_classes = (EXPORT_SCENE_OT_bristle_brush, IMPORT_SCENE_OT_bristle_brush)


def register():
    for cls in _classes:
        bpy.utils.register_class(cls)
    bpy.types.TOPBAR_MT_file_export.append(_menu_export)
    bpy.types.TOPBAR_MT_file_import.append(_menu_import)


def unregister():
    bpy.types.TOPBAR_MT_file_import.remove(_menu_import)
    bpy.types.TOPBAR_MT_file_export.remove(_menu_export)
    for cls in reversed(_classes):
        bpy.utils.unregister_class(cls)


# ---------------------------------------------------------------------------
# Command line

USAGE = ("usage: blender -b [FILE.blend] --python-exit-code 1 --python bristle_brush.py -- "
         "[--armature NAME] [--import BRUSH.json] [--save FILE.blend] [OUT.json]")


def _parse_args(argv):
    opts = {"armature": None, "import": None, "save": None, "out": None}
    i = 0
    while i < len(argv):
        arg = argv[i]
        if arg in ("-h", "--help"):
            print(USAGE)
            print("  OUT.json            export the brush (the only armature, the active one, or --armature)")
            print("  --import BRUSH.json build the brush in the scene first (one Blender unit = 1 mm)")
            print("  --save FILE.blend   save the .blend afterwards")
            sys.exit(0)
        if arg in ("--armature", "--import", "--save"):
            if i + 1 >= len(argv):
                raise BrushError("%s needs a value; %s" % (arg, USAGE), EXIT_USAGE)
            opts[arg[2:]] = argv[i + 1]
            i += 2
            continue
        if arg.startswith("-"):
            raise BrushError("unknown option '%s'; %s" % (arg, USAGE), EXIT_USAGE)
        if opts["out"] is not None:
            raise BrushError("more than one output file ('%s', '%s'); %s" % (opts["out"], arg, USAGE),
                             EXIT_USAGE)
        opts["out"] = arg
        i += 1
    if opts["out"] is None and opts["import"] is None:
        raise BrushError("nothing to do: give OUT.json and/or --import BRUSH.json; " + USAGE, EXIT_USAGE)
    return opts


def main(argv):
    """Command-line form; returns the exit code. Messages go to stderr, one line each,
    prefixed with the .blend file name (or "scene")."""
    source = os.path.basename(bpy.data.filepath) if bpy.data.filepath else "scene"

    def warn(message):
        sys.stderr.write("bristle_brush: %s: warning: %s\n" % (source, message))

    try:
        opts = _parse_args(argv)
        arm_name = opts["armature"]
        if opts["import"]:
            arm = import_brush_file(bpy.context, opts["import"])
            arm_name = arm.name
        if opts["out"]:
            scene = bpy.context.scene
            brush = export_brush(scene, find_armature(scene, arm_name), warn)
            write_brush_file(opts["out"], brush)
        if opts["save"]:
            try:
                bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(opts["save"]))
            except RuntimeError as e:
                raise BrushError("%s: cannot save: %s" % (opts["save"], str(e).strip().splitlines()[-1]),
                                 EXIT_CANT_CREATE)
    except BrushError as e:
        sys.stderr.write("bristle_brush: %s: %s\n" % (source, e))
        return e.code
    return 0


if __name__ == "__main__":
    args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    sys.stdout.flush()
    code = main(args)
    sys.stdout.flush()
    sys.stderr.flush()
    sys.exit(code)
