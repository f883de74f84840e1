#!/usr/bin/env python3
"""The engine's layering (docs/design.md, "Layers"): each sub-folder of engine/
includes only itself and the sub-folders below it in LAYERS, and no engine file
includes a folder built on the engine (render/, input/, batch/, haptics/, cli/).
Each sub-folder's CMake target links only the parts below it, too.

  layering.py SOURCE_DIR    exit 0 when the tree keeps the order, 1 naming each
                            include (or link) that breaks it
  layering.py --self-test   runs the check on a made-up tree with one upward
                            include and one include of render/, and fails unless
                            both are caught and a clean tree passes
"""
import os
import re
import sys
import tempfile

# Bottom first. A file may include its own folder and any folder before it.
LAYERS = ["base", "model", "mechanics", "solvers", "solvers/ipopt", "dynamics", "geometry",
          "paint", "formats"]
ABOVE_ENGINE = ("render/", "input/", "batch/", "haptics/", "cli/", "process/", "api/")
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


def check(root):
    return check_includes(root) + check_links(root)


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
        clean = check(root)
        if clean:
            print("self-test: a clean tree failed:\n  " + "\n  ".join(clean), file=sys.stderr)
            return 1
        # One upward include (base reaching the model), one include of render/,
        # one upward link.
        write(root, "engine/base/text_file.cpp", '#include "engine/model/brush.h"\n')
        write(root, "engine/geometry/strips.cpp", '  #  include "render/png_io.h"\n')
        write(root, "engine/mechanics/CMakeLists.txt",
              "target_link_libraries(bristle_engine_mechanics PUBLIC\n"
              "  bristle_engine_model bristle_engine_dynamics)\n")
        found = check(root)
        wanted = ["engine/base/text_file.cpp: includes engine/model/brush.h",
                  "engine/geometry/strips.cpp: includes render/png_io.h",
                  "bristle_engine_mechanics links bristle_engine_dynamics"]
        missed = [w for w in wanted if not any(w in p for p in found)]
        if missed or len(found) != len(wanted):
            print("self-test: expected exactly\n  " + "\n  ".join(wanted) +
                  "\nfound\n  " + "\n  ".join(found), file=sys.stderr)
            return 1
    print("self-test: the upward include, the include of render/ and the upward link caught")
    return 0


def main():
    if sys.argv[1:] == ["--self-test"]:
        return self_test()
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        return 64
    problems = check(sys.argv[1])
    if problems:
        print(f"{len(problems)} breaks of the engine's layering ({' < '.join(LAYERS)}):",
              file=sys.stderr)
        for p in problems:
            print(f"  {p}", file=sys.stderr)
        return 1
    print(f"engine layering kept: {' < '.join(LAYERS)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
