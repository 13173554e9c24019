"""The Python module's overhead: scene.intersect on camera_rays against trident-bench's render of the
same rays, same structure, traversal and threads, in pairs.

    PYTHONPATH=build/python /usr/bin/python3 bench/python_bench.py \
        --scenes ../shared/scenes/scenes.json --accel bvh,kdtree,octree --simd simd16 --threads 2

Each round runs `build/trident-bench ... --repeats R` (render ms: the median of R runs after one
warm-up) and then times R calls of scene.intersect(rays) after one warm-up, the same R (median).
A round's ratio is module over C++; the table gives the medians over rounds of both times and of
the ratios. trident-bench traces every ray (--tile-culling off), as the module traces every ray it
is given. Before timing, the module's hits are compared with trident-bench's hit buffer
(--dump-hits): identical triangle and t, or the row says how many differ.
"""
import argparse
import json
import os
import pathlib
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import trident

REPO = pathlib.Path(__file__).resolve().parents[1]
TRAVERSALS = {"scalar": "scalar", "simd4": "4", "simd8": "8", "simd16": "16"}


def load_scene(name, manifest):
    """(vertices, triangles, camera, bench arguments naming the scene) for a manifest entry or built-in."""
    if manifest:
        entries = {e["name"]: e for e in json.loads(manifest.read_text())}
        if name in entries:
            vertices, triangles = trident.load_obj(manifest.parent / entries[name]["file"])
            return vertices, triangles, entries[name]["camera"], ["--scenes", str(manifest), "--only", name]
    scene = trident.builtin_scene(name)
    return scene["vertices"], scene["triangles"], scene["camera"], ["--only", name]


def bench_render_ms(args, scene_args, accel, traversal, threads, dump_dir=None, report=None):
    """trident-bench's median render time of one configuration; its JSON's machine into `report`."""
    with tempfile.TemporaryDirectory() as tmp:
        out = pathlib.Path(tmp) / "row.json"
        command = [str(args.bench), *scene_args, "--accel", accel, "--simd", traversal, "--threads", str(threads),
                   "--width", str(args.width), "--height", str(args.height), "--repeats", str(args.repeats),
                   "--embree", "none", "--reference", "self", "--quiet", "--json", str(out),
                   # Every ray traced, as the module traces every ray of its arrays.
                   "--tile-culling", "off"]
        if dump_dir:
            command += ["--dump-hits", str(dump_dir)]
        subprocess.run(command, check=True, stdout=subprocess.DEVNULL)
        data = json.loads(out.read_text())
        if report is not None:
            report["machine"] = data["machine"]
        (row,) = data["rows"]
        return row["render_ms"]


def module_render_ms(scene, rays, simd, threads, repeats):
    """Median of `repeats` timed scene.intersect calls after one warm-up."""
    scene.intersect(rays, threads=threads, simd=simd)
    samples = []
    for _ in range(repeats):
        start = time.perf_counter()
        scene.intersect(rays, threads=threads, simd=simd)
        samples.append((time.perf_counter() - start) * 1000.0)
    return statistics.median(samples)


def differing_hits(args, scene_args, scene, rays, accel, traversal, threads):
    """Rays whose triangle or t differ between the module and trident-bench's hit buffer."""
    with tempfile.TemporaryDirectory() as tmp:
        bench_render_ms(args, scene_args, accel, traversal, threads, dump_dir=tmp)
        (path,) = pathlib.Path(tmp).glob(f"*.{accel}.{traversal}.hits")
        triangle, t = trident.read_hit_buffer(path)
    hits = scene.intersect(rays, threads=threads, simd=TRAVERSALS[traversal])
    return int(np.count_nonzero((hits.triangle != triangle) | (hits.t != t)))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", type=pathlib.Path, help="BENCHMARK.md manifest (default: built-in scenes)")
    parser.add_argument("--only", help="scene names, comma-separated (default: all of the manifest, or teapot)")
    parser.add_argument("--accel", default="bvh,kdtree,octree")
    parser.add_argument("--simd", default="simd16", help="traversals: scalar,simd4,simd8,simd16")
    parser.add_argument("--threads", type=int, default=0, help="0: all cores, as both sides default to")
    parser.add_argument("--width", type=int, default=1920)
    parser.add_argument("--height", type=int, default=1080)
    parser.add_argument("--repeats", type=int, default=5, help="timed runs per side and round")
    parser.add_argument("--rounds", type=int, default=5, help="pairs of (trident-bench, module) runs")
    parser.add_argument("--bench", type=pathlib.Path, default=REPO / "build" / "trident-bench")
    parser.add_argument("--json", type=pathlib.Path, help="write the rows here")
    args = parser.parse_args()

    if args.only:
        names = args.only.split(",")
    elif args.scenes:
        names = [e["name"] for e in json.loads(args.scenes.read_text())]
    else:
        names = ["teapot"]
    thread_count = args.threads or len(os.sched_getaffinity(0))
    rows, report = [], {}
    print(f"{args.width}x{args.height}, {args.repeats} runs per side and round, {args.rounds} rounds; "
          f"trident {trident.__file__}", flush=True)
    print("| scene | structure | traversal | threads | C++ render ms | module intersect ms | module / C++ "
          "| differing hits |\n|---|---|---|---|---|---|---|---|", flush=True)
    for name in names:
        vertices, triangles, camera, scene_args = load_scene(name, args.scenes)
        rays = trident.camera_rays(camera["eye"], camera["target"], camera["up"], camera.get("fov_y_deg", 60.0),
                                   args.width, args.height)
        for accel in args.accel.split(","):
            scene = trident.Scene(vertices, triangles, accel=accel)
            for traversal in args.simd.split(","):
                differing = differing_hits(args, scene_args, scene, rays, accel, traversal, thread_count)
                cpp, module, ratios = [], [], []
                for _ in range(args.rounds):
                    cpp.append(bench_render_ms(args, scene_args, accel, traversal, thread_count, report=report))
                    module.append(module_render_ms(scene, rays, TRAVERSALS[traversal], thread_count, args.repeats))
                    ratios.append(module[-1] / cpp[-1])
                row = dict(scene=name, structure=accel, traversal=traversal, threads=thread_count,
                           cpp_render_ms=statistics.median(cpp), module_intersect_ms=statistics.median(module),
                           ratio=statistics.median(ratios), ratio_min=min(ratios), ratio_max=max(ratios),
                           differing_hits=differing, cpp_samples=cpp, module_samples=module)
                rows.append(row)
                print(f"| {name} | {accel} | {traversal} | {thread_count} | {row['cpp_render_ms']:.2f} | "
                      f"{row['module_intersect_ms']:.2f} | {row['ratio']:.3f} ({min(ratios):.3f}..{max(ratios):.3f}) "
                      f"| {differing} |", flush=True)
    if args.json:
        args.json.write_text(json.dumps({"command": sys.argv, "width": args.width, "height": args.height,
                                         "rounds": args.rounds, "repeats": args.repeats, **report, "rows": rows},
                                        indent=1))
    return 1 if any(r["differing_hits"] for r in rows) else 0


if __name__ == "__main__":
    sys.exit(main())
