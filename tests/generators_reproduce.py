#!/usr/bin/env python3
"""Fails when a generated library folder differs from what its generator
writes: scenes/brushes/generate.py and scenes/paintings/generate.py
(docs/brush-format.md: the brush files are generated; docs/scene-format.md:
so are the paintings). Each generator is copied into a fresh temporary
folder and run there, so that it writes beside the copy and never into the
tree; every file it writes must equal the tree's file of the same path,
byte for byte. A generator edited without running it, or a generated file
edited by hand, shows here as the files that differ.
  generators_reproduce.py SOURCE_DIR
  generators_reproduce.py --self-test   (a tree with one edited file fails)"""
import filecmp
import os
import shutil
import subprocess
import sys
import tempfile

GENERATORS = ["scenes/brushes/generate.py", "scenes/paintings/generate.py"]


def differing(source_dir, rel):
    """Paths (relative to the generator's folder) that the generator writes
    differently from the tree, or writes where the tree has none."""
    folder = os.path.join(source_dir, os.path.dirname(rel))
    with tempfile.TemporaryDirectory() as tmp:
        shutil.copy(os.path.join(source_dir, rel), tmp)
        subprocess.run([sys.executable, os.path.join(tmp, os.path.basename(rel))],
                       check=True, cwd=tmp)
        bad = []
        for root, _, files in os.walk(tmp):
            for f in files:
                written = os.path.join(root, f)
                sub = os.path.relpath(written, tmp)
                if sub == os.path.basename(rel) or "__pycache__" in sub:
                    continue
                tree = os.path.join(folder, sub)
                if not os.path.isfile(tree) or not filecmp.cmp(written, tree, shallow=False):
                    bad.append(sub)
        return sorted(bad)


def check(source_dir):
    problems = []
    for rel in GENERATORS:
        for sub in differing(source_dir, rel):
            problems.append(f"{os.path.join(os.path.dirname(rel), sub)}: differs from what "
                            f"{rel} writes (run it, or edit it instead of the file)")
    return problems


def self_test():
    """A copy of the generated folders with one file edited must fail."""
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    with tempfile.TemporaryDirectory() as tmp:
        for rel in GENERATORS:
            shutil.copytree(os.path.join(root, os.path.dirname(rel)),
                            os.path.join(tmp, os.path.dirname(rel)))
        if check(tmp):
            print("self-test: the untouched copy already differs", file=sys.stderr)
            return 1
        with open(os.path.join(tmp, "scenes/paintings/calligraphy.json"), "a") as f:
            f.write(" ")
        problems = check(tmp)
        if problems != ["scenes/paintings/calligraphy.json: differs from what "
                        "scenes/paintings/generate.py writes (run it, or edit it instead of "
                        "the file)"]:
            print("self-test: an edited scene was not the one file named: %s" % problems,
                  file=sys.stderr)
            return 1
    print("self-test: an edited generated file is caught")
    return 0


def main():
    if sys.argv[1:] == ["--self-test"]:
        return self_test()
    if len(sys.argv) != 2:
        print("usage: generators_reproduce.py SOURCE_DIR | --self-test", file=sys.stderr)
        return 64
    problems = check(sys.argv[1])
    for p in problems:
        print(p, file=sys.stderr)
    if not problems:
        print("every generated file is what its generator writes")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
