#!/usr/bin/env python3
"""Fails when a Catch test case is not run by exactly one ctest test of its own
name. ctest learns the test cases of each test program by listing them
(catch_discover_tests), and CMake splits a name at every ';': a case named
"a; b" became two ctest tests, "a" and " b", each matching no case, each
passing in a few milliseconds while the case itself never ran. Reads the
build directory's test list (`ctest --show-only=json-v1`), asks each test
program for its case names (`--list-test-names-only`) and names every case
that no ctest test runs, and every ctest test that runs no case."""
import json
import subprocess
import sys


def main():
    if len(sys.argv) != 2:
        print("usage: every_test_case_runs.py BUILD_DIR", file=sys.stderr)
        return 64
    out = subprocess.run(["ctest", "--show-only=json-v1"], cwd=sys.argv[1],
                         check=True, capture_output=True, text=True).stdout
    by_program = {}
    for t in json.loads(out)["tests"]:
        cmd = t.get("command") or []
        # A discovered Catch case: the program, then the case's name.
        if len(cmd) >= 2 and cmd[0].split("/")[-1].startswith("test_"):
            by_program.setdefault(cmd[0], set()).add(t["name"])
    problems = []
    cases_total = 0
    for program, ctest_names in sorted(by_program.items()):
        # (Catch 2 exits with the number of cases listed, not 0.)
        listed = subprocess.run([program, "--list-test-names-only"],
                                capture_output=True, text=True).stdout
        cases = {line for line in listed.splitlines() if line.strip()}
        cases_total += len(cases)
        name = program.split("/")[-1]
        for c in sorted(cases - ctest_names):
            problems.append(f"{name}: case {c!r} is run by no ctest test (a ';' in its name?)")
        for n in sorted(ctest_names - cases):
            problems.append(f"{name}: ctest test {n!r} runs no case")
    if not by_program:
        print("no Catch test programs found in the ctest list", file=sys.stderr)
        return 1
    if problems:
        print(f"{len(problems)} problems:", file=sys.stderr)
        for p in problems:
            print(f"  {p}", file=sys.stderr)
        return 1
    print(f"all {cases_total} cases of {len(by_program)} programs run under ctest")
    return 0


if __name__ == "__main__":
    sys.exit(main())
