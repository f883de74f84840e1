# The library round trip of scripts/blender/test_bristle_brush.py in two Blender
# runs instead of two per brush:
#
#   blender -b --factory-startup --python-exit-code 1 --python round_trip.py -- import OUTDIR A.json ...
#       imports each brush into an empty scene, saves OUTDIR/<name>.blend
#   blender -b --factory-startup --python-exit-code 1 --python round_trip.py -- export OUTDIR A.blend ...
#       opens each .blend, exports its brush to OUTDIR/<name>.json
#
# It calls the same functions as bristle_brush.py's command line; warnings are printed
# to stderr in the same "bristle_brush: FILE: warning: ..." form, errors end the run.

import os
import sys

import bpy

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import bristle_brush  # noqa: E402

mode, out_dir, *paths = sys.argv[sys.argv.index("--") + 1:]
for path in paths:
    name = os.path.splitext(os.path.basename(path))[0]

    def warn(message, source=os.path.basename(path)):
        sys.stderr.write("bristle_brush: %s: warning: %s\n" % (source, message))

    try:
        if mode == "import":
            bpy.ops.wm.read_factory_settings(use_empty=True)
            bristle_brush.import_brush(bpy.context, bristle_brush.read_brush_file(path))
            bpy.ops.wm.save_as_mainfile(filepath=os.path.join(out_dir, name + ".blend"))
        else:
            bpy.ops.wm.open_mainfile(filepath=path)
            scene = bpy.context.scene
            brush = bristle_brush.export_brush(scene, bristle_brush.find_armature(scene), warn)
            bristle_brush.write_brush_file(os.path.join(out_dir, name + ".json"), brush)
    except bristle_brush.BrushError as e:
        sys.stderr.write("bristle_brush: %s: %s\n" % (os.path.basename(path), e))
        sys.exit(e.code)
