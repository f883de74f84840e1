# Checks, inside Blender, that posing the imported bones deforms the cage the way
# bristle skins it (docs/brush-format.md "Skinning", docs/blender.md §5): for every
# library brush with a surface, bend every joint, pose the bones to match, and compare
# Blender's Armature-modifier result with
#     p = sum_w (x'_k + F'_k F_k^T (c - x_k))
# computed here in double precision from the brush file, where x_k, F_k are point k
# and the frame of the segment that starts there (the last segment's at the tip), at
# rest and bent (').
#
#   blender -b --factory-startup --python-exit-code 1 --python check_skinning.py -- A.json ...
# Prints the largest deviation per brush; exits 1 if one exceeds TOL_MM.

import os
import sys

import bpy
from mathutils import Matrix

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import bristle_brush as bb  # noqa: E402

# Blender deforms in float32: a 30 mm coordinate carries 2e-6 mm per rounding, and the
# deform matrices (pose x inverse rest) take about a dozen roundings: ~2.4e-5 mm
# (measured on the library: at most 6e-6 mm). A wrong bone/point assignment moves
# vertices by millimetres.
TOL_MM = 1e-4
# The bend added to every joint's rest angles (rad): theta towards +y, phi towards -x,
# most at the ferrule, like a brush pressed and dragged (|angles| stay <= 1.2).
BEND = [(0.35, -0.10), (0.30, -0.08), (0.25, -0.05), (0.20, 0.0), (0.15, 0.0)]


def frames_and_points(spine, angles):
    frame = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    frames, points = [], [list(spine["root_mm"])]
    for length, (t, p) in zip(spine["segment_lengths_mm"], angles):
        frame = bb._matmul(frame, bb._joint_rotation(t, p))
        d = bb._matvec(frame, [0.0, 0.0, -1.0])
        frames.append(frame)
        points.append([points[-1][i] + length * d[i] for i in range(3)])
    return frames + [frames[-1]], points  # the tip takes the last segment's frame


failed = False
for path in sys.argv[sys.argv.index("--") + 1:]:
    brush = bb.read_brush_file(path)
    if "surface" not in brush:
        continue
    bpy.ops.wm.read_factory_settings(use_empty=True)
    arm = bb.import_brush(bpy.context, brush)  # 1 Blender unit = 1 mm
    cage = next(o for o in bpy.context.scene.objects if o.type == 'MESH')
    cage.modifiers["Subdivision"].show_viewport = False  # compare the cage itself

    rest, bent = [], []
    for s, spine in enumerate(brush["spines"]):
        n = len(spine["segment_lengths_mm"])
        angles = spine.get("rest_angles_rad", [[0.0, 0.0]] * n)
        bent_angles = [[a[0] + BEND[min(k, len(BEND) - 1)][0], a[1] + BEND[min(k, len(BEND) - 1)][1]]
                       for k, a in enumerate(angles)]
        rest.append(frames_and_points(spine, angles))
        bent.append(frames_and_points(spine, bent_angles))
        # Pose bone k: rotate its rest orientation by F'_k F_k^T and put its head at x'_k.
        for k in range(n):
            bone = arm.data.bones[bb.bone_name(s, k)]
            turn = bb._matmul(bent[s][0][k], bb._transpose(rest[s][0][k]))
            m = Matrix(turn).to_4x4() @ bone.matrix_local.to_3x3().to_4x4()
            m.translation = bent[s][1][k]
            arm.pose.bones[bone.name].matrix = m
            bpy.context.view_layer.update()  # children are set relative to this pose

    evaluated = cage.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = evaluated.to_mesh()
    worst = displacement = 0.0
    for vi, (c, entries) in enumerate(zip(brush["surface"]["cage_vertices_mm"], brush["surface"]["skin"])):
        want = [0.0, 0.0, 0.0]
        for s, point, w in entries:
            f0, x0 = rest[s][0][point], rest[s][1][point]
            f1, x1 = bent[s][0][point], bent[s][1][point]
            local = bb._matvec(bb._transpose(f0), bb._sub(c, x0))
            p = bb._matvec(f1, local)
            want = [want[i] + w * (x1[i] + p[i]) for i in range(3)]
        got = list(mesh.vertices[vi].co)
        worst = max(worst, bb._norm(bb._sub(got, want)))
        displacement = max(displacement, bb._norm(bb._sub(got, c)))
    evaluated.to_mesh_clear()
    name = os.path.basename(path)
    print("check_skinning: %s: cage moved up to %.1f mm; largest deviation %.2e mm (tolerance %g)"
          % (name, displacement, worst, TOL_MM))
    # The bend must move the cage by millimetres, or the comparison proves nothing.
    if not worst <= TOL_MM or displacement < 1.0:
        failed = True
        print("check_skinning: %s: FAILED" % name)
sys.exit(1 if failed else 0)
