# Builds the .blend fixtures of scripts/blender/test_bristle_brush.py, programmatically,
# the way a user would model a brush: an armature whose bone chains are the spines,
# a cage mesh with vertex groups named after the bones, custom properties.
#
#   blender -b --factory-startup --python-exit-code 1 --python make_fixtures.py -- OUTDIR
#
# Writes OUTDIR/<case>.blend for every case and OUTDIR/handmade.expected.json, the
# brush the hand-made model stands for, computed here in double precision from the
# design numbers (not from Blender's float32 geometry).

import json
import math
import os
import sys

import bpy
from mathutils import Vector

OUT = sys.argv[sys.argv.index("--") + 1]

# The design, in mm and in the brush frame (origin at the ferrule mouth, hairs
# along -z). Three spines of three segments, 20 mm of hair, roots on a triangle.
ROOTS = [[0.0, 1.5, 0.0], [1.3, -0.75, 0.0], [-1.3, -0.75, 0.0]]
LENGTHS = [8.0, 7.0, 5.0]
# (theta, phi) per joint, eq. 10: spine 0 leans 0.1 rad towards +y and bends its
# tip 0.2 rad towards -x of its parent; spine 1 leans 0.15 rad towards +x
# (phi = -0.15), spine 2 towards -x; both turn their tips back in by 0.12 rad.
ANGLES = [
    [[0.1, 0.0], [0.0, 0.0], [0.0, 0.2]],
    [[0.0, -0.15], [0.0, 0.0], [0.0, 0.12]],
    [[0.0, 0.15], [0.0, 0.0], [0.0, -0.12]],
]
WIDTHS = [2.4, 2.6, 2.0, 0.6]
STIFFNESS = [9.0, 7.0, 5.5]
DAMPING = [0.006, 0.005, 0.004]
PROPS = {"description": "made in Blender by make_fixtures.py", "mu_static": 0.45,
         "mu_kinetic": 0.35, "anisotropy_strength": 0.3, "anisotropy_exponent": 2.0,
         "strips_count": 80, "strips_seed": 4, "strips_root_width_mm": 0.12,
         "paint_capacity": 1.1}
RING_RADIUS_MM = 4.5
RING_VERTICES = 6
TIP_DEPTH_MM = 21.0
M_PER_MM = 0.001  # the model is built in metres: scene unit scale 1 (the factory setting)


def rot(theta, phi):
    """Ry(phi) Rx(theta), written out directly (eq. 10)."""
    ct, st, cp, sp = math.cos(theta), math.sin(theta), math.cos(phi), math.sin(phi)
    return [[cp, sp * st, sp * ct], [0.0, ct, -st], [-sp, cp * st, cp * ct]]


def mul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def points_of(s):
    frame = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    pts = [ROOTS[s]]
    for length, (t, p) in zip(LENGTHS, ANGLES[s]):
        frame = mul(frame, rot(t, p))
        d = [-frame[i][2] for i in range(3)]  # F (0, 0, -1)
        pts.append([pts[-1][i] + length * d[i] for i in range(3)])
    return pts


POINTS = [points_of(s) for s in range(3)]


def cage_design():
    """A hexagonal tube: a ring at the ferrule mouth (skinned to the roots), a ring
    level with point 2 (skinned to point 2) and a tip vertex (skinned to the three
    tips, point 3). Each ring vertex: 0.7 on its nearest spine, 0.3 on the next."""
    verts, skin = [], []
    levels = [(0, 0.0), (2, -sum(LENGTHS[:2]))]
    for point, z in levels:
        for i in range(RING_VERTICES):
            a = 2 * math.pi * i / RING_VERTICES
            v = [RING_RADIUS_MM * math.cos(a), RING_RADIUS_MM * math.sin(a), z]
            near = sorted(range(3), key=lambda s: (v[0] - POINTS[s][point][0]) ** 2 +
                          (v[1] - POINTS[s][point][1]) ** 2)
            verts.append(v)
            skin.append(sorted([[near[0], point, 0.7], [near[1], point, 0.3]]))
    verts.append([0.0, 0.0, -TIP_DEPTH_MM])
    skin.append([[0, 3, 0.333334], [1, 3, 0.333333], [2, 3, 0.333333]])
    m = RING_VERTICES
    faces = [[i, m + i, m + (i + 1) % m, (i + 1) % m] for i in range(m)]
    faces += [[m + i, 2 * m, m + (i + 1) % m] for i in range(m)]
    return verts, faces, skin


def bone_name(s, k):
    return "hair%d.%d" % (s, k)


def reset():
    bpy.ops.wm.read_factory_settings(use_empty=True)


def build_handmade(name="handmade", pose_props_on=2):
    """The hand-made brush. The armature object is moved and turned (unit scale): the
    brush frame is its local frame. The cage object sits at the world origin, so its
    vertices are the brush-frame design mapped through the armature's transform."""
    scene = bpy.context.scene
    scene.unit_settings.system = 'METRIC'
    scene.unit_settings.scale_length = 1.0
    arm_data = bpy.data.armatures.new(name)
    arm = bpy.data.objects.new(name, arm_data)
    scene.collection.objects.link(arm)
    arm.location = (0.02, -0.01, 0.05)  # 5 cm away: float32 noise stays < 1e-5 mm
    arm.rotation_euler = (0.0, 0.0, math.radians(30))
    bpy.context.view_layer.objects.active = arm
    bpy.context.view_layer.update()
    bpy.ops.object.mode_set(mode='EDIT')
    for s in range(3):
        parent = None
        for k in range(3):
            eb = arm_data.edit_bones.new(bone_name(s, k))
            eb.head = [c * M_PER_MM for c in POINTS[s][k]]
            eb.tail = [c * M_PER_MM for c in POINTS[s][k + 1]]
            eb.head_radius = WIDTHS[k] / 2 * M_PER_MM
            eb.tail_radius = WIDTHS[k + 1] / 2 * M_PER_MM
            if parent:
                eb.parent = parent
                eb.use_connect = True
            parent = eb
    bpy.ops.object.mode_set(mode='OBJECT')
    for s in range(3):
        for k in range(3):
            # Spine 2 keeps its properties on the pose bones (the pose-mode panel).
            name_k = bone_name(s, k)
            holder = arm.pose.bones[name_k] if s == pose_props_on else arm_data.bones[name_k]
            holder["stiffness_nmm_per_rad"] = STIFFNESS[k]
            holder["damping_nmm"] = DAMPING[k]
    for key, value in PROPS.items():
        arm[key] = value

    verts, faces, skin = cage_design()
    world = arm.matrix_world.copy()
    mesh = bpy.data.meshes.new(name + "-cage")
    mesh.from_pydata([world @ Vector([c * M_PER_MM for c in v]) for v in verts], [], faces)
    cage = bpy.data.objects.new(name + "-cage", mesh)
    scene.collection.objects.link(cage)
    groups = {}
    for s in range(3):
        for k in range(3):
            groups[bone_name(s, k)] = cage.vertex_groups.new(name=bone_name(s, k))
    for vi, entries in enumerate(skin):
        for s, point, w in entries:
            groups[bone_name(s, min(point, 2))].add([vi], w, 'REPLACE')
    mod = cage.modifiers.new("Armature", 'ARMATURE')
    mod.object = arm
    sub = cage.modifiers.new("Subdivision", 'SUBSURF')
    sub.levels = 2
    return arm, cage, skin


def save(case):
    bpy.ops.wm.save_as_mainfile(filepath=os.path.join(OUT, case + ".blend"))


def expected_handmade():
    verts, faces, skin = cage_design()
    spines = [{
        "root_mm": ROOTS[s], "segment_lengths_mm": LENGTHS, "stiffness_nmm_per_rad": STIFFNESS,
        "damping_nmm": DAMPING, "rest_angles_rad": ANGLES[s], "width_mm": WIDTHS}
        for s in range(3)]
    return {
        "format": "bristle-brush/1", "name": "handmade", "description": PROPS["description"],
        "spines": spines,
        "friction": {"mu_static": 0.45, "mu_kinetic": 0.35,
                     "anisotropy": {"strength": 0.3, "exponent": 2.0}},
        "surface": {"cage_vertices_mm": verts, "faces": faces, "skin": skin,
                    "refinement_level": 2},
        "strips": {"count": 80, "seed": 4, "root_width_mm": 0.12},
        "paint": {"capacity": 1.1},
    }


os.makedirs(OUT, exist_ok=True)
with open(os.path.join(OUT, "handmade.expected.json"), "w") as f:
    json.dump(expected_handmade(), f, indent=1)

reset()
build_handmade()
save("handmade")

# Error and warning cases, each one change to the hand-made brush.
reset()
bpy.ops.mesh.primitive_cube_add()
save("no-armature")

reset()
arm, cage, _ = build_handmade()
bpy.context.view_layer.objects.active = arm
bpy.ops.object.mode_set(mode='EDIT')
fork = arm.data.edit_bones.new("hair0.2b")  # a second child of hair0.1
fork.head = arm.data.edit_bones["hair0.1"].tail
fork.tail = [c * M_PER_MM for c in (2.0, 2.0, -20.0)]
fork.parent = arm.data.edit_bones["hair0.1"]
fork.use_connect = True
bpy.ops.object.mode_set(mode='OBJECT')
save("branching")

reset()
arm, cage, _ = build_handmade()
cage.vertex_groups.clear()
save("no-groups")

reset()
arm, cage, _ = build_handmade()
cage.vertex_groups.new(name="Group")
save("stray-group")

reset()
arm, cage, _ = build_handmade()
arm.scale = (2.0, 2.0, 2.0)
save("scaled")

reset()
arm, cage, _ = build_handmade()
for v in cage.data.vertices[:RING_VERTICES]:  # the mouth ring's weights now sum to 0.5
    for g in v.groups:
        g.weight *= 0.5
save("unnormalised")

reset()
arm, cage, _ = build_handmade()
for b in arm.data.bones:
    if "stiffness_nmm_per_rad" in b.keys():
        del b["stiffness_nmm_per_rad"]
for b in arm.pose.bones:
    if "stiffness_nmm_per_rad" in b.keys():
        del b["stiffness_nmm_per_rad"]
for key in ("mu_static", "mu_kinetic"):
    del arm[key]
save("missing-props")

reset()
arm, cage, _ = build_handmade()
arm["mu_static"] = 3.0
save("bad-friction")

reset()
arm, cage, _ = build_handmade()
arm["strips_cont"] = 80
save("misspelt-prop")

reset()
arm, cage, _ = build_handmade()
arm.data.bones["hair1.0"]["stiffness_nmm_per_rad"] = -2.0
save("bad-stiffness")

reset()
build_handmade("first")
second, _, _ = build_handmade("second")
bpy.context.view_layer.objects.active = None
save("two-armatures")

reset()
arm, cage, _ = build_handmade()
for pb in arm.pose.bones:  # a pose is not the rest shape: the export must ignore it
    pb.rotation_mode = 'XYZ'
    pb.rotation_euler = (0.4, 0.1, -0.2)
save("posed")

reset()
arm, cage, _ = build_handmade()
# What Ctrl+P > Armature Deform > With Automatic Weights does to a cage that already has a
# Subdivision Surface modifier: the Armature modifier ends up after it.
bpy.context.view_layer.objects.active = cage
bpy.ops.object.modifier_move_to_index(modifier="Armature", index=1)
save("modifier-order")

reset()
arm, cage, _ = build_handmade()
mesh = cage.data
verts = [v.co.copy() for v in mesh.vertices]
faces = [list(p.vertices) for p in mesh.polygons]
faces[0:2] = [[faces[0][0], faces[0][1], faces[0][2], faces[1][2], faces[0][3]]]  # two quads -> a pentagon
new = bpy.data.meshes.new("ngon")
new.from_pydata(verts, [], faces)
cage.data = new  # the group names stay on the object; faces are checked before weights
save("ngon")

reset()
arm, cage, _ = build_handmade()
bpy.context.view_layer.objects.active = arm
bpy.ops.object.mode_set(mode='EDIT')
for eb in arm.data.edit_bones:  # the whole brush 1 mm up: roots inside the ferrule
    eb.head.z += 1 * M_PER_MM
    eb.tail.z += 1 * M_PER_MM
bpy.ops.object.mode_set(mode='OBJECT')
save("root-above")

reset()
# The non-programmer's path: a cage with no weights and no Armature modifier, parented
# with Ctrl+P > Armature Deform > With Automatic Weights (bone heat), which also adds
# the modifier (after the Subdivision Surface modifier the cage already has).
arm, cage, _ = build_handmade()
cage.vertex_groups.clear()
cage.modifiers.remove(cage.modifiers["Armature"])
bpy.context.view_layer.update()  # the cage's base exists from here on: it can be selected
for o in bpy.context.view_layer.objects:
    o.select_set(o in (arm, cage))
bpy.context.view_layer.objects.active = arm
bpy.ops.object.parent_set(type='ARMATURE_AUTO')
assert cage.parent == arm and cage.vertex_groups, "automatic weights failed"
save("auto-weights")
