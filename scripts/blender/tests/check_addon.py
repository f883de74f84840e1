# Checks bristle_brush.py as an add-on, inside Blender: register() adds the File >
# Import and File > Export entries, the import operator builds a brush, the export
# operator writes it back (OUTDIR/addon-<name>.json, compared by the caller), an
# export with nothing to export and an import of a broken brush are refused with the
# reason (leaving the scene as it was), unregister() cleans up.
#
#   blender -b --factory-startup --python-exit-code 1 --python check_addon.py -- BRUSH.json OUTDIR
# Exits non-zero (an AssertionError) on the first failed check.

import os
import sys

import bpy

brush_path, out_dir = sys.argv[sys.argv.index("--") + 1:][:2]
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import bristle_brush  # noqa: E402

assert bristle_brush.bl_info["blender"] <= (3, 4, 0)
bpy.ops.wm.read_factory_settings(use_empty=True)
bristle_brush.register()


def menu_entries(menu):
    return getattr(menu.draw, "_draw_funcs", [])


assert bristle_brush._menu_export in menu_entries(bpy.types.TOPBAR_MT_file_export)
assert bristle_brush._menu_import in menu_entries(bpy.types.TOPBAR_MT_file_import)

# Nothing to export in an empty scene: the operator is cancelled with the reason.
try:
    bpy.ops.export_scene.bristle_brush(filepath=os.path.join(out_dir, "addon-empty.json"))
    raise AssertionError("exporting an empty scene succeeded")
except RuntimeError as e:  # bpy turns an operator's ERROR report into RuntimeError
    assert "no armature" in str(e), str(e)
assert not os.path.exists(os.path.join(out_dir, "addon-empty.json"))

# A brush the importer cannot build (spine 0 has no stiffness values): refused, and
# nothing half-built is left in the scene.
import json  # noqa: E402
with open(brush_path) as f:
    broken = json.load(f)
broken["spines"][0]["stiffness_nmm_per_rad"] = []
broken_path = os.path.join(out_dir, "addon-broken.json")
with open(broken_path, "w") as f:
    json.dump(broken, f)
try:
    bpy.ops.import_scene.bristle_brush(filepath=broken_path)
    raise AssertionError("importing a broken brush succeeded")
except RuntimeError as e:
    assert "not a valid bristle brush" in str(e), str(e)
assert len(bpy.context.scene.objects) == 0, list(bpy.context.scene.objects)

name = os.path.splitext(os.path.basename(brush_path))[0]
assert bpy.ops.import_scene.bristle_brush(filepath=brush_path) == {'FINISHED'}
arm = bpy.data.objects[name]
assert arm.type == 'ARMATURE' and abs(bpy.context.scene.unit_settings.scale_length - 0.001) < 1e-9  # float32
assert bpy.ops.export_scene.bristle_brush(
    filepath=os.path.join(out_dir, "addon-%s.json" % name)) == {'FINISHED'}

bristle_brush.unregister()
assert bristle_brush._menu_export not in menu_entries(bpy.types.TOPBAR_MT_file_export)
assert not hasattr(bpy.ops.export_scene, "bristle_brush") or \
    "bristle_brush" not in dir(bpy.ops.export_scene)
print("check_addon: ok")
