# Renders the pictures of docs/blender.md with Blender itself (Workbench, headless):
#
#   blender -b --factory-startup --python-exit-code 1 --python scripts/blender/render_doc_images.py -- \
#       scenes/brushes/round.json docs/images
#
# writes docs/images/blender-rest.png (the imported brush at rest: spines as tubes
# of their envelope widths inside the subdivided cage) and blender-posed.png (the
# bones posed as if the brush were pressed onto the paper and dragged towards -y,
# the cage following through its vertex-group weights).

import math
import os
import sys

import bpy
from mathutils import Matrix, Vector

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bristle_brush  # noqa: E402

brush_path, out_dir = sys.argv[sys.argv.index("--") + 1:][:2]
bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
arm = bristle_brush.import_brush(bpy.context, bristle_brush.read_brush_file(brush_path))
cage = next(o for o in scene.objects if o.type == 'MESH' and o.parent == arm)


def material(name, rgba):
    m = bpy.data.materials.new(name)
    m.diffuse_color = rgba
    return m


# Spines: a thin rod per bone with a ball at its head (the spine's points), bone-
# parented so that they follow the pose (armatures themselves do not render). Rods
# stand for the spine axes only: their widths are what the cage encloses.
spine_mat = material("spine", (0.85, 0.35, 0.08, 1.0))
ROD_MM, BALL_MM = 0.18, 0.45
for bone in arm.data.bones:
    length = bone.length
    bpy.ops.mesh.primitive_cylinder_add(vertices=12, radius=ROD_MM, depth=length)
    rod = bpy.context.object
    bpy.ops.mesh.primitive_uv_sphere_add(segments=16, ring_count=8, radius=BALL_MM,
                                         location=(0, 0, -length / 2))
    ball = bpy.context.object
    for o in (rod, ball):
        o.data.materials.append(spine_mat)
        for p in o.data.polygons:
            p.use_smooth = True
        # The cylinder runs along its local z: turn -z onto the bone's y axis (head to
        # tail) and put it at the bone's middle, in bone space.
        o.parent = arm
        o.parent_type = 'BONE'
        o.parent_bone = bone.name
        bpy.context.view_layer.update()
        o.matrix_world = arm.matrix_world @ bone.matrix_local @ \
            Matrix.Translation((0, length / 2, 0)) @ Matrix.Rotation(math.radians(90), 4, 'X')

# The cage as bristle uses it: skinned (Armature modifier), then subdivided; drawn
# as the wires of the refined surface so the spines stay visible inside it.
cage.data.materials.append(material("cage", (0.15, 0.35, 0.85, 1.0)))
wire = cage.modifiers.new("Wireframe", 'WIREFRAME')
wire.thickness = 0.09
wire.use_even_offset = True

# A ferrule above the mouth (z > 0), as wide as the cage's mouth ring.
mouth = max(math.hypot(v.co.x, v.co.y) for v in cage.data.vertices if abs(v.co.z) < 1e-3)
bpy.ops.mesh.primitive_cylinder_add(vertices=48, radius=mouth * 0.75, depth=8, location=(0, 0, 4))
ferrule = bpy.context.object
ferrule.parent = arm
ferrule.data.materials.append(material("ferrule", (0.7, 0.7, 0.72, 1.0)))

# The paper, level with the lowest rest tip for the rest picture.
lowest = min((arm.matrix_world @ b.tail_local).z for b in arm.data.bones)
bpy.ops.mesh.primitive_plane_add(size=60, location=(0, 0, lowest - 0.05))
paper = bpy.context.object
paper.data.materials.append(material("paper", (1.0, 0.98, 0.93, 1.0)))

cam_data = bpy.data.cameras.new("camera")
cam_data.lens = 60
cam = bpy.data.objects.new("camera", cam_data)
scene.collection.objects.link(cam)
scene.camera = cam
target = Vector((0, 0, lowest * 0.4))
cam.location = target + Vector((60, -22, 14))
cam.rotation_euler = (target - cam.location).to_track_quat('-Z', 'Y').to_euler()

scene.render.engine = 'BLENDER_WORKBENCH'
scene.render.resolution_x, scene.render.resolution_y = 640, 560
scene.render.resolution_percentage = 100
scene.render.image_settings.file_format = 'PNG'
scene.render.image_settings.color_mode = 'RGB'
scene.render.image_settings.compression = 100
scene.render.film_transparent = False
shading = scene.display.shading
shading.light = 'STUDIO'
shading.color_type = 'MATERIAL'
shading.show_shadows = True
shading.show_cavity = False
scene.display.render_aa = '8'
scene.world = bpy.data.worlds.new("world")
scene.world.color = (1.0, 1.0, 1.0)


def render(name):
    scene.render.filepath = os.path.join(os.path.abspath(out_dir), name)
    bpy.ops.render.render(write_still=True)


render("blender-rest.png")

# Pose: press the brush down and drag it towards -y: every spine bends about the
# bones' x axis, most at the ferrule and along the belly; the paper moves up to
# the posed tips (the lowest of them touches it).
bend_deg = [24, 20, 16, 12, 8, 6, 4, 2]
for pb in arm.pose.bones:
    k = int(pb.name.rsplit(".", 1)[1])
    pb.rotation_mode = 'XYZ'
    pb.rotation_euler = (math.radians(bend_deg[min(k, len(bend_deg) - 1)]), 0, 0)
bpy.context.view_layer.update()
posed_lowest = min((arm.matrix_world @ pb.tail).z for pb in arm.pose.bones)
paper.location.z = posed_lowest - 0.05
render("blender-posed.png")
print("render_doc_images: wrote blender-rest.png and blender-posed.png to", out_dir)
