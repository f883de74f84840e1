#!/usr/bin/env python3
"""The layering of the engine and of render/ (docs/design.md, "Layers").

Each sub-folder of engine/ includes only itself and the sub-folders below it in
LAYERS, and no engine file includes a folder built on the engine (render/,
input/, batch/, haptics/, cli/). Each sub-folder's CMake target links only the
parts below it, too. Each folder of render/ includes only the render folders
RENDER_INCLUDES allows it; render/image, which `bristle batch` links to read
PNG text, includes no GL header and its CMake target links no OSMesa and no
GL part.

  layering.py SOURCE_DIR    exit 0 when the tree keeps the order, 1 naming each
                            include (or link) that breaks it
  layering.py --self-test   runs the check on a made-up tree with one upward
                            include in the engine, one include of render/ from
                            it, one upward link, and in render/ one upward
                            include, one GL header and one OSMesa link in
                            render/image, and fails unless each is caught and
                            a clean tree passes
"""
import os
import re
import sys
import tempfile

# Bottom first. A file may include its own folder and any folder before it.
LAYERS = ["base", "model", "mechanics", "solvers", "solvers/ipopt", "dynamics", "geometry",
          "paint", "formats"]
ABOVE_ENGINE = ("render/", "input/", "batch/", "haptics/", "cli/", "process/", "api/")
# render/'s folders ("" is render/ itself) and the render folders each may
# include: images need no GL, GL no images; previews draw with both; the stroke,
# scene and sheet renderers sit on image and gl but not on the previews.
RENDER_INCLUDES = {"image": {"image"}, "gl": {"gl"}, "preview": {"image", "gl", "preview"},
                   "": {"image", "gl", ""}}
GL_HEADER = re.compile(r"^(GL|EGL|GLES\w*)/|osmesa", re.IGNORECASE)
# What render/image's CMake target must not link: OSMesa, or a render part with GL.
GL_LINK = re.compile(r"OSMESA|OpenGL|bristle(_|::)render_(gl|preview)\b|bristle(_|::)render\b(?!_)")
INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]([^">]+)[">]', re.MULTILINE)
LINK = re.compile(r"target_link_libraries\(bristle_engine_(\w+)([^)]*)\)")


def layer_of(folder):
    """The rank of an engine sub-folder ("solvers/ipopt"), or None if undeclared."""
    return LAYERS.index(folder) if folder in LAYERS else None


def check_includes(root):
    problems = []
    engine = os.path.join(root, "engine")
    for dirpath, _, names in sorted(os.walk(engine)):
        for name in sorted(names):
            if not name.endswith((".h", ".cpp")):
                continue
            path = os.path.join(dirpath, name)
            rel = os.path.relpath(path, root)
            own_folder = os.path.relpath(dirpath, engine).replace(os.sep, "/")
            own = layer_of(own_folder)
            if own is None:
                problems.append(f"{rel}: engine/{own_folder}/ is not a declared layer")
                continue
            with open(path, encoding="utf-8") as f:
                text = f.read()
            for inc in INCLUDE.findall(text):
                if inc.startswith(ABOVE_ENGINE):
                    problems.append(f"{rel}: includes {inc}, a folder built on the engine")
                elif inc.startswith("engine/"):
                    folder = os.path.dirname(inc[len("engine/"):])
                    theirs = layer_of(folder)
                    if theirs is None:
                        problems.append(f"{rel}: includes {inc}, not in a declared layer")
                    elif theirs > own:
                        problems.append(f"{rel}: includes {inc}, engine/{folder}/ is above "
                                        f"engine/{own_folder}/")
    return problems


def check_links(root):
    """Each part's target_link_libraries names only bristle_engine_<part> below it."""
    problems = []
    targets = {layer.replace("/", "_"): i for i, layer in enumerate(LAYERS)}
    for layer in LAYERS:
        path = os.path.join(root, "engine", layer, "CMakeLists.txt")
        if not os.path.exists(path):
            continue
        with open(path, encoding="utf-8") as f:
            text = f.read()
        for target, args in LINK.findall(text):
            own = targets.get(target)
            for dep in re.findall(r"bristle_engine_(\w+)", args):
                theirs = targets.get(dep)
                if own is None or theirs is None or theirs >= own:
                    problems.append(f"engine/{layer}/CMakeLists.txt: bristle_engine_{target} "
                                    f"links bristle_engine_{dep}, not a part below it")
    return problems


def render_folder(inc):
    """The render folder of an include ("image", "" for render/ itself), or None."""
    if not inc.startswith("render/"):
        return None
    return os.path.dirname(inc[len("render/"):])


def check_render(root):
    """Each render folder includes only the render folders RENDER_INCLUDES allows;
    render/image includes no GL header and links nothing with GL."""
    problems = []
    render = os.path.join(root, "render")
    for dirpath, _, names in sorted(os.walk(render)):
        own = os.path.relpath(dirpath, render).replace(os.sep, "/")
        own = "" if own == "." else own
        for name in sorted(names):
            rel = os.path.relpath(os.path.join(dirpath, name), root)
            if name == "CMakeLists.txt" and own == "image":
                with open(os.path.join(dirpath, name), encoding="utf-8") as f:
                    for link in GL_LINK.finditer(f.read()):
                        problems.append(f"{rel}: links {link.group(0)}, and render/image "
                                        "has no GL")
            if not name.endswith((".h", ".cpp")):
                continue
            if own not in RENDER_INCLUDES:
                problems.append(f"{rel}: render/{own}/ is not a declared render folder")
                continue
            with open(os.path.join(dirpath, name), encoding="utf-8") as f:
                text = f.read()
            for inc in INCLUDE.findall(text):
                folder = render_folder(inc)
                if folder is not None and folder not in RENDER_INCLUDES[own]:
                    problems.append(f"{rel}: includes {inc}, render/{own or '.'} may include "
                                    "only render/" +
                                    ", render/".join(sorted(f or "." for f in RENDER_INCLUDES[own])))
                if own == "image" and GL_HEADER.search(inc):
                    problems.append(f"{rel}: includes {inc}, a GL header in render/image")
    return problems


def check(root):
    return check_includes(root) + check_links(root) + check_render(root)


def write(root, rel, text):
    path = os.path.join(root, rel)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w", encoding="utf-8") as f:
        f.write(text)


def self_test():
    with tempfile.TemporaryDirectory() as root:
        write(root, "engine/base/error.h", "#pragma once\n#include <string>\n")
        write(root, "engine/model/brush.h", '#pragma once\n#include "engine/base/error.h"\n')
        write(root, "engine/solvers/ipopt/ipopt_solver.cpp",
              '#include "engine/model/brush.h"\n#include "engine/solvers/ipopt/x.h"\n')
        write(root, "engine/model/CMakeLists.txt",
              "target_link_libraries(bristle_engine_model PUBLIC bristle_engine_base)\n")
        write(root, "render/image/png_io.cpp", '#include "render/image/png_io.h"\n')
        write(root, "render/image/CMakeLists.txt",
              "target_link_libraries(bristle_render_image PRIVATE PNG::PNG)\n")
        write(root, "render/gl/gl_context.cpp", "#include <GL/osmesa.h>\n")
        write(root, "render/preview/preview.cpp",
              '#include "render/gl/gl_context.h"\n#include "render/image/text.h"\n')
        write(root, "render/stroke.cpp",
              '#include "render/gl/footprint.h"\n#include "render/image/compose.h"\n')
        clean = check(root)
        if clean:
            print("self-test: a clean tree failed:\n  " + "\n  ".join(clean), file=sys.stderr)
            return 1
        # One upward include (base reaching the model), one include of render/,
        # one upward link.
        write(root, "engine/base/text_file.cpp", '#include "engine/model/brush.h"\n')
        write(root, "engine/geometry/strips.cpp", '  #  include "render/image/png_io.h"\n')
        write(root, "engine/mechanics/CMakeLists.txt",
              "target_link_libraries(bristle_engine_mechanics PUBLIC\n"
              "  bristle_engine_model bristle_engine_dynamics)\n")
        # In render/: image reaching up to gl, a GL header and OSMesa in image, and
        # the stroke renderers reaching a preview.
        write(root, "render/image/compose.cpp", '#include "render/gl/gl_context.h"\n')
        write(root, "render/image/text.cpp", "#include <GL/gl.h>\n")
        write(root, "render/image/CMakeLists.txt",
              "target_link_libraries(bristle_render_image PRIVATE PNG::PNG PkgConfig::OSMESA)\n")
        write(root, "render/sheet.cpp", '#include "render/preview/preview.h"\n')
        found = check(root)
        wanted = ["engine/base/text_file.cpp: includes engine/model/brush.h",
                  "engine/geometry/strips.cpp: includes render/image/png_io.h",
                  "bristle_engine_mechanics links bristle_engine_dynamics",
                  "render/image/compose.cpp: includes render/gl/gl_context.h",
                  "render/image/text.cpp: includes GL/gl.h",
                  "render/image/CMakeLists.txt: links OSMESA",
                  "render/sheet.cpp: includes render/preview/preview.h"]
        missed = [w for w in wanted if not any(w in p for p in found)]
        if missed or len(found) != len(wanted):
            print("self-test: expected exactly\n  " + "\n  ".join(wanted) +
                  "\nfound\n  " + "\n  ".join(found), file=sys.stderr)
            return 1
    print("self-test: the engine's upward include, include of render/ and upward link, and "
          "render/'s upward includes, GL header and OSMesa link in render/image caught")
    return 0


def main():
    if sys.argv[1:] == ["--self-test"]:
        return self_test()
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        return 64
    problems = check(sys.argv[1])
    if problems:
        print(f"{len(problems)} breaks of the layering (engine: {' < '.join(LAYERS)}; "
              "render: image, gl < preview; image, gl < render/):", file=sys.stderr)
        for p in problems:
            print(f"  {p}", file=sys.stderr)
        return 1
    print(f"engine layering kept: {' < '.join(LAYERS)}; render layering kept: image (no GL), "
          "gl < preview; image, gl < render/")
    return 0


if __name__ == "__main__":
    sys.exit(main())
