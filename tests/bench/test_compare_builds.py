#!/usr/bin/python3
"""bench/compare_builds.py on a tiny run: the built trident-bench against itself.

    /usr/bin/python3 tests/bench/test_compare_builds.py BUILD_DIR

Two rounds over the teapot and two structures (with the asteroid too, the test took 80 s
under the sanitizers): one table row per scene, structure, traversal and
ray kind the runs share, each ratio a positive number, the Markdown file the same table; a binary
that does not exist is one line on stderr and exit 1.
"""
import os
import subprocess
import sys
import tempfile

SCRIPT = os.path.join(os.path.dirname(__file__), "..", "..", "bench", "compare_builds.py")


def main():
    bench = os.path.join(sys.argv[1], "trident-bench")
    failures = []
    with tempfile.TemporaryDirectory() as scratch:
        markdown = os.path.join(scratch, "compare.md")
        done = subprocess.run([sys.executable, SCRIPT, bench, bench, "--rounds", "2", "--each-scene", "teapot",
                               "--each-accel", "bvh,octree", "--markdown", markdown, "--", "--simd", "scalar,simd4",
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
