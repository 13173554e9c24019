#!/usr/bin/python3
"""bench/compare_builds.py on a tiny run: the built trident-bench against itself.

    /usr/bin/python3 tests/bench/test_compare_builds.py BUILD_DIR

Two rounds over the teapot and two structures (with the asteroid too, the test took 80 s
under the sanitizers): one table row per scene, structure, traversal and
ray kind the runs share, each ratio a positive number, the Markdown file the same table, the JSON
file the same rows with every round's ratio; a binary
that does not exist is one line on stderr and exit 1.
"""
import json
import os
import subprocess
import sys
import tempfile

SCRIPT = os.path.join(os.path.dirname(__file__), "..", "..", "bench", "compare_builds.py")


def main():
    bench = os.path.join(sys.argv[1], "trident-bench")
    failures = []
    with tempfile.TemporaryDirectory() as scratch:
        markdown, json_path = os.path.join(scratch, "compare.md"), os.path.join(scratch, "compare.json")
        done = subprocess.run([sys.executable, SCRIPT, bench, bench, "--rounds", "2", "--each-scene", "teapot",
                               "--each-accel", "bvh,octree", "--markdown", markdown, "--json", json_path, "--", "--simd", "scalar,simd4",
                               "--rays", "primary,shadow", "--threads", "1", "--embree", "none", "--width", "32",
                               "--height", "18", "--repeats", "1"], capture_output=True, text=True)
        if done.returncode != 0:
            failures.append("exit {}: {}".format(done.returncode, done.stderr.strip()))
        rows = [line for line in done.stdout.splitlines() if line.startswith("| teapot |")]
        if len(rows) != 2 * 2 * 2:  # structures x traversals x ray kinds
            failures.append("expected 8 rows, got {}:\n{}".format(len(rows), done.stdout))
        for row in rows:
            ratios = [float(x) for x in row.strip("|").split("|")[5:8]]
            if not all(r > 0 for r in ratios) or not ratios[1] <= ratios[0] <= ratios[2]:
                failures.append("ratios out of order or not positive: " + row)
        if os.path.exists(markdown):
            with open(markdown) as f:
                if f.read() != done.stdout:
                    failures.append("the Markdown file differs from what was printed")
        else:
            failures.append("no Markdown file written")
        if os.path.exists(json_path):
            with open(json_path) as f:
                report = json.load(f)
            printed = {tuple(x.strip() for x in row.strip("|").split("|")[:4]) +
                       tuple(round(float(x), 3) for x in row.strip("|").split("|")[5:8]) for row in rows}
            stored = {(r["scene"], r["structure"], r["traversal"], r["rays"], round(r["median"], 3),
                       round(r["min"], 3), round(r["max"], 3)) for r in report["rows"]}
            if printed != stored:
                failures.append("the JSON rows differ from the table: {} against {}".format(stored, printed))
            if any(len(r["ratios"]) != 2 for r in report["rows"]) or report["rounds"] != 2:
                failures.append("the JSON should hold both rounds' ratios of every row")
            if not report.get("machine", {}).get("cpu"):
                failures.append("the JSON names no CPU")
        else:
            failures.append("no JSON file written")
        missing = subprocess.run([sys.executable, SCRIPT, os.path.join(scratch, "nothing"), bench, "--", "--threads", "1"],
                                 capture_output=True, text=True)
        if missing.returncode != 1 or len(missing.stderr.strip().splitlines()) != 1:
            failures.append("a missing binary: exit {}, stderr {!r}".format(missing.returncode, missing.stderr))
    for failure in failures:
        print("FAIL " + failure)
    print("compare_builds: {} rows, {}".format(len(rows), "failed" if failures else "ok"))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
