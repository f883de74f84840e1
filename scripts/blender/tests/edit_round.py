# An edit a user would make to the imported round brush, run before the exporter:
#
#   blender -b round.blend --python-exit-code 1 --python edit_round.py \
#       --python ../bristle_brush.py -- round-edited.json
#
# - spine 0's tip segment (bone spine0.3) is turned 0.1 rad further towards +y in Edit
#   Mode: its rest angle theta goes from 0 to 0.1;
# - its stiffness is lowered to 4 N mm/rad in the bone's Custom Properties;
# - the armature's mu_static is raised to 0.5.

import os
import sys

import bpy

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import bristle_brush as bb  # noqa: E402

arm = bpy.data.objects["round"]
bpy.context.view_layer.objects.active = arm
# Where the tail goes: round's spine 0 has rest angles [[0.03, 0], [0, 0], [0, 0], [0, 0]].
bones = [arm.data.bones["spine0.%d" % k] for k in range(4)]
root = list(bones[0].head_local)
lengths = [b.length for b in bones]
tip = bb.spine_points(root, lengths, [[0.03, 0.0], [0.0, 0.0], [0.0, 0.0], [0.1, 0.0]])[4]
bpy.ops.object.mode_set(mode='EDIT')
arm.data.edit_bones["spine0.3"].tail = tip
bpy.ops.object.mode_set(mode='OBJECT')
arm.data.bones["spine0.3"]["stiffness_nmm_per_rad"] = 4.0
arm["mu_static"] = 0.5
