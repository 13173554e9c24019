"""Load an OBJ, trace BENCHMARK.md's camera over it with trident, save a depth image.

    PYTHONPATH=build/python /usr/bin/python3 examples/depth_image.py MESH.obj depth.png \
        [--eye X Y Z --target X Y Z --up X Y Z --fov 60 --width 640 --height 360 --accel bvh]

Without --eye and --target the camera looks at the mesh's bounding box from its front (+z).
"""
import argparse

import matplotlib

matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt
import numpy as np

import trident


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mesh")
    parser.add_argument("output")
    parser.add_argument("--eye", type=float, nargs=3)
    parser.add_argument("--target", type=float, nargs=3)
    parser.add_argument("--up", type=float, nargs=3, default=(0.0, 1.0, 0.0))
    parser.add_argument("--fov", type=float, default=60.0)
    parser.add_argument("--width", type=int, default=640)
    parser.add_argument("--height", type=int, default=360)
    parser.add_argument("--accel", default="bvh", choices=["bvh", "kdtree", "octree", "brute"])
    args = parser.parse_args()

    vertices, triangles = trident.load_obj(args.mesh)
    scene = trident.Scene(vertices, triangles, accel=args.accel)
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    target = args.target if args.target else (lo + hi) / 2
    eye = args.eye if args.eye else np.asarray(target) + [0.0, 0.0, 1.5 * np.linalg.norm(hi - lo)]
    rays = trident.camera_rays(eye, target, args.up, args.fov, args.width, args.height)
    hits = scene.intersect(rays)

    depth = np.ma.masked_invalid(hits.t)  # misses (t = inf) stay transparent
    plt.imsave(args.output, depth, cmap="viridis_r")
    print(f"{args.output}: {np.isfinite(hits.t).mean():.1%} of {hits.t.size} rays hit; {scene!r}")


if __name__ == "__main__":
    main()
