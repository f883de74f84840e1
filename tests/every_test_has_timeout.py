#!/usr/bin/env python3
"""Fails when a ctest test has no TIMEOUT (tests/CMakeLists.txt says why every
test needs one). Reads the test list of the build directory given, as ctest
itself reports it (`ctest --show-only=json-v1`), and names the tests that lack
one; exit 0 when all have it."""
import json
import subprocess
import sys


def main():
    if len(sys.argv) != 2:
        print("usage: every_test_has_timeout.py BUILD_DIR", file=sys.stderr)
        return 64
    out = subprocess.run(["ctest", "--show-only=json-v1"], cwd=sys.argv[1],
                         check=True, capture_output=True, text=True).stdout
    tests = json.loads(out)["tests"]
    missing = []
    for t in tests:
        props = {p["name"]: p["value"] for p in t.get("properties", [])}
        if not props.get("TIMEOUT"):
            missing.append(t["name"])
    if missing:
        print(f"{len(missing)} of {len(tests)} tests have no TIMEOUT:", file=sys.stderr)
        for name in missing:
            print(f"  {name}", file=sys.stderr)
        return 1
    print(f"all {len(tests)} tests have a TIMEOUT")
    return 0


if __name__ == "__main__":
    sys.exit(main())
