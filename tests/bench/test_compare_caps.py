#!/usr/bin/python3
"""bench/compare_caps.py on a tiny run of the built benchmark, and its byte comparison by hand.

    /usr/bin/python3 tests/bench/test_compare_caps.py BUILD_DIR

The teapot at 33x19 (no multiple of any packet block), the wide BVH and the octree: every cap
this CPU runs gives one row per structure and width the cap allows, each with no differing ray,
and the JSON names the CPU; a record changed by hand is one differing ray, a header changed is
every ray; a binary that does not exist is one line on stderr and exit 1.
"""
import json
import os
import subprocess
import sys
import tempfile

BENCH_DIR = os.path.join(os.path.dirname(__file__), "..", "..", "bench")
SCRIPT = os.path.join(BENCH_DIR, "compare_caps.py")
sys.path.insert(0, BENCH_DIR)

import compare_caps  # noqa: E402


def main():
    bench = os.path.join(sys.argv[1], "trident-bench")
    failures = []
    rows = []
    with tempfile.TemporaryDirectory() as scratch:
        json_path = os.path.join(scratch, "caps.json")
        done = subprocess.run([sys.executable, SCRIPT, bench, "--json", json_path, "--", "--only", "teapot",
                               "--accel", "bvh,octree", "--threads", "2", "--width", "33", "--height", "19"],
                              capture_output=True, text=True)
        if done.returncode != 0:
            failures.append("exit {}: {}".format(done.returncode, done.stderr.strip()))
        elif not os.path.exists(json_path):
            failures.append("no JSON file written")
        else:
            with open(json_path) as f:
                report = json.load(f)
            rows = report["rows"]
            ran = [cap for cap in compare_caps.CAP_WIDTHS if cap not in {s["cap"] for s in report["skipped"]}]
            expected = {("bvh", w, cap) for cap in ran for w in compare_caps.CAP_WIDTHS[cap]} | \
                       {("octree", w, cap) for cap in ran for w in compare_caps.CAP_WIDTHS[cap]}
            got = {(r["structure"], r["traversal"], r["cap"]) for r in rows}
            if "sse4" not in ran or got != expected:
                failures.append("rows {} against {}".format(sorted(got), sorted(expected)))
            if any(r["differing_rays"] != 0 or r["rays"] != 33 * 19 for r in rows):
                failures.append("rows with differing rays or the wrong ray count: {}".format(rows))
            if not report.get("machine", {}).get("cpu"):
                failures.append("the JSON names no CPU")
    header = b"RTHITS1\0" + (2).to_bytes(4, "little") + (1).to_bytes(4, "little")
    a = header + b"\xff\xff\xff\xff\x00\x00\x80\x7f" + (5).to_bytes(4, "little") + b"\x00\x00\x80\x3f"
    b = header + b"\xff\xff\xff\xff\x00\x00\x80\x7f" + (5).to_bytes(4, "little") + b"\x01\x00\x80\x3f"
    if compare_caps.differing_rays(a, a) != 0 or compare_caps.differing_rays(a, b) != 1:
        failures.append("differing_rays: one t's last bit changed should be one ray")
    if compare_caps.differing_rays(a, b"RTHITS1\0" + (1).to_bytes(4, "little") + a[12:]) != 2:
        failures.append("differing_rays: another width should be every ray")
    missing = subprocess.run([sys.executable, SCRIPT, os.path.join(os.path.dirname(bench), "nothing"), "--json",
                              os.path.join(tempfile.gettempdir(), "unused.json")], capture_output=True, text=True)
    if missing.returncode != 1 or len(missing.stderr.strip().splitlines()) != 1:
        failures.append("a missing binary: exit {}, stderr {!r}".format(missing.returncode, missing.stderr))
    for failure in failures:
        print("FAIL " + failure)
    print("compare_caps: {} rows, {}".format(len(rows), "failed" if failures else "ok"))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
