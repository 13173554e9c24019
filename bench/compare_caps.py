#!/usr/bin/python3
"""The same hits under every ISA cap: trident-bench's hit buffers, cap by cap, byte for byte.

    /usr/bin/python3 bench/compare_caps.py build-portable/trident-bench --json caps.json \\
        -- --scenes ../shared/scenes/scenes.json --accel bvh,bvh2,kdtree,octree --threads 2

The portable build runs its SSE4.2, AVX2 or AVX-512 kernels by what the CPU has, capped by
TRIDENT_ISA (simd/README.md), and promises the same hits whichever it runs. This runs the binary
once without a cap (single rays: the reference) and once under each cap, with every packet width the
cap allows, each run writing its primary rays' hit buffers (BENCHMARK.md's format, --dump-hits),
and compares every capped buffer with the reference buffer of the same scene and structure, byte
for byte: a row per scene, structure, traversal and cap, with how many rays differ. A cap the CPU
cannot run (trident-bench refuses the widths it names) is listed as skipped, not failed.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

# The packet widths each cap allows (simd/README.md): SSE4.2 has 4 lanes, AVX2 8, AVX-512 16.
CAP_WIDTHS = {"sse4": ["scalar", "simd4"], "avx2": ["scalar", "simd4", "simd8"],
              "avx512": ["scalar", "simd4", "simd8", "simd16"]}
HEADER_BYTES = 16  # BENCHMARK.md: the magic "RTHITS1\0", then the width and the height (32 bits each)
RECORD_BYTES = 8  # per pixel: the triangle index and t (32 bits each)


def run(binary, cap, simd, bench_args, hits_dir, json_path):
    """Runs trident-bench under `cap` (None: TRIDENT_ISA unset); the process's result."""
    env = dict(os.environ)
    env.pop("TRIDENT_ISA", None)
    if cap:
        env["TRIDENT_ISA"] = cap
    command = [binary] + bench_args + ["--rays", "primary", "--simd", ",".join(simd), "--embree", "none",
                                       "--reference", "self", "--repeats", "1", "--quiet",
                                       "--dump-hits", hits_dir, "--json", json_path]
    print("{}: {}".format("TRIDENT_ISA=" + cap if cap else "no cap", " ".join(command)), file=sys.stderr, flush=True)
    return subprocess.run(command, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)


def differing_rays(a, b):
    """Rays whose records differ between two hit buffers of the same rays (all of them when the
    headers or sizes differ)."""
    if a[:HEADER_BYTES] != b[:HEADER_BYTES] or len(a) != len(b):
        return (max(len(a), len(b)) - HEADER_BYTES) // RECORD_BYTES
    return sum(a[i:i + RECORD_BYTES] != b[i:i + RECORD_BYTES] for i in range(HEADER_BYTES, len(a), RECORD_BYTES))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                     usage="%(prog)s BINARY --json FILE -- BENCH_ARGS...")
    parser.add_argument("binary", help="a portable trident-bench (TRIDENT_MARCH=portable)")
    parser.add_argument("--json", required=True, help="write the rows here (bench/results_page.py reads it)")
    argv = sys.argv[1:]
    split = argv.index("--") if "--" in argv else len(argv)
    args = parser.parse_args(argv[:split])
    bench_args = argv[split + 1:]
    if not os.access(args.binary, os.X_OK):
        sys.exit("compare_caps.py: {}: not an executable".format(args.binary))

    rows, skipped = [], []
    with tempfile.TemporaryDirectory() as scratch:
        reference_dir = os.path.join(scratch, "reference")
        done = run(args.binary, None, ["scalar"], bench_args, reference_dir, os.path.join(scratch, "reference.json"))
        if done.returncode != 0:
            sys.exit("compare_caps.py: the reference run failed ({}): {}".format(done.returncode, done.stderr.strip()))
        with open(os.path.join(scratch, "reference.json")) as f:
            report = json.load(f)
        for cap, widths in CAP_WIDTHS.items():
            cap_dir = os.path.join(scratch, cap)
            done = run(args.binary, cap, widths, bench_args, cap_dir, os.path.join(scratch, cap + ".json"))
            if done.returncode != 0:
                skipped.append({"cap": cap, "why": done.stderr.strip().splitlines()[-1] if done.stderr.strip() else
                                "exit {}".format(done.returncode)})
                continue
            for name in sorted(os.listdir(cap_dir)):
                scene, structure, traversal, _ = name.rsplit(".", 3)
                reference_path = os.path.join(reference_dir, "{}.{}.scalar.hits".format(scene, structure))
                with open(os.path.join(cap_dir, name), "rb") as f:
                    capped = f.read()
                with open(reference_path, "rb") as f:
                    reference = f.read()
                rows.append({"scene": scene, "structure": structure, "traversal": traversal, "cap": cap,
                             "rays": (len(reference) - HEADER_BYTES) // RECORD_BYTES,
                             "differing_rays": differing_rays(capped, reference)})
    if not rows:
        sys.exit("compare_caps.py: no hit buffers compared: {}".format("; ".join(s["why"] for s in skipped)))
    with open(args.json, "w") as f:
        json.dump({"tool": "compare_caps.py", "machine": report["machine"], "width": report["width"],
                   "height": report["height"], "command_line": " ".join(bench_args), "rows": rows,
                   "skipped": skipped}, f, indent=2)
        f.write("\n")
    differ = [r for r in rows if r["differing_rays"]]
    print("compare_caps.py: {} hit buffers under {} caps, {} differ from the uncapped single rays'{}".format(
        len(rows), len(CAP_WIDTHS) - len(skipped), len(differ),
        "".join("; {} {} {} {}: {} rays".format(r["scene"], r["structure"], r["traversal"], r["cap"],
                                                 r["differing_rays"]) for r in differ)))
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main())
