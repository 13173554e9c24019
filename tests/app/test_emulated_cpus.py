#!/usr/bin/python3
"""A portable build on CPUs this machine is not: an SSE4.2 and an AVX2 one, emulated by qemu-x86_64.

    /usr/bin/python3 tests/app/test_emulated_cpus.py build/trident

qemu's user-mode emulator (Debian's qemu-user; its TCG has no AVX-512) runs the binary as a Nehalem
(x86-64-v2, SSE4.2) and as a Haswell (x86-64-v3, AVX2). On each, every structure is rendered with
single rays, with --simd auto and with every width the CPU has: each run must succeed and write the
hit buffer this machine writes, bit for bit; a width the CPU lacks must be refused with one line
naming the missing instruction set; `trident cpu` must say which kernels it chose. An AVX-512 or
AVX2 instruction outside the dispatched kernels would end a run with SIGILL here. Exit 0 when all
holds, 1 otherwise; 0 with a message when qemu-x86_64 is absent.
"""
import math
import os
import shutil
import subprocess
import sys
import tempfile

CPUS = {  # qemu's model: the widths it runs, the widths it must refuse and the reason named
    "Nehalem": (["scalar", "auto", "4"], {"8": "AVX2", "16": "AVX-512"}, "--simd auto: 4"),
    "Haswell": (["scalar", "auto", "4", "8"], {"16": "AVX-512"}, "--simd auto: 8"),
}
# The brute force is left out: emulated, it took most of the test's time (its kernels run under
# every ISA cap on this CPU in tests/app/test_trace.cpp).
STRUCTURES = ["bvh", "bvh2", "kdtree", "octree"]
RENDER = ["--width", "32", "--height", "20", "--threads", "1"]
# The scene: three overlapping spheres on a floor, 1,058 triangles, written as an OBJ. Emulated,
# the builds were most of each run: the teapot's 6,320 triangles took 0.25 s (Nehalem) to 1.0 s
# (Haswell) to build as a wide BVH, against 27 ms to trace; a sixth of the triangles still gives
# every structure a tree of several levels, and the image hits and misses.
SPHERES = [((0.0, 1.0, 0.0), 1.0), ((1.3, 0.7, 0.4), 0.7), ((-1.1, 0.5, 0.8), 0.5)]
SEGMENTS, RINGS = 16, 12


def write_scene(path):
    vertices, faces = [(-2.0, 0.0, -2.0), (2.0, 0.0, -2.0), (2.0, 0.0, 2.0), (-2.0, 0.0, 2.0)], [(1, 3, 2), (1, 4, 3)]
    for (cx, cy, cz), radius in SPHERES:
        first = len(vertices) + 1
        for ring in range(RINGS + 1):
            theta = math.pi * ring / RINGS
            for segment in range(SEGMENTS):
                phi = 2.0 * math.pi * segment / SEGMENTS
                vertices.append((cx + radius * math.sin(theta) * math.cos(phi), cy + radius * math.cos(theta),
                                 cz + radius * math.sin(theta) * math.sin(phi)))
        for ring in range(RINGS):
            for segment in range(SEGMENTS):
                a = first + ring * SEGMENTS + segment
                b = first + ring * SEGMENTS + (segment + 1) % SEGMENTS
                c, d = a + SEGMENTS, b + SEGMENTS
                if ring > 0:
                    faces.append((a, b, c))  # the top ring's would have zero area
                if ring < RINGS - 1:
                    faces.append((b, d, c))  # and the bottom ring's
    with open(path, "w") as f:
        f.writelines("v {:.6f} {:.6f} {:.6f}\n".format(*v) for v in vertices)
        f.writelines("f {} {} {}\n".format(*face) for face in faces)


def run(command):
    return subprocess.run(command, capture_output=True, text=True)


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: test_emulated_cpus.py TRIDENT_BINARY")
    trident = sys.argv[1]
    qemu = shutil.which("qemu-x86_64")
    if qemu is None:
        print("test_emulated_cpus.py: skipped, qemu-x86_64 is not installed (Debian's qemu-user)")
        return 0
    failures = []
    with tempfile.TemporaryDirectory() as scratch:
        scene = os.path.join(scratch, "spheres.obj")
        write_scene(scene)

        def render(prefix, structure, simd, name):
            hits = os.path.join(scratch, name + ".hits")
            done = run(prefix + [trident, "render", scene] + RENDER +
                       ["--accel", structure, "--simd", simd, "--output", os.path.join(scratch, "image.png"),
                        "--dump-hits", hits])
            return done, hits

        for structure in STRUCTURES:
            done, here = render([], structure, "scalar", structure + ".here")
            if done.returncode != 0:
                failures.append("{} on this CPU: {}".format(structure, done.stderr.strip()))
                continue
            with open(here, "rb") as f:
                expected = f.read()
            for cpu, (widths, refused, _) in CPUS.items():
                for simd in widths:
                    label = "{} --accel {} --simd {}".format(cpu, structure, simd)
                    done, hits = render([qemu, "-cpu", cpu], structure, simd, "{}.{}.{}".format(cpu, structure, simd))
                    if done.returncode != 0:
                        failures.append("{}: exit {}: {}".format(label, done.returncode, done.stderr.strip()[-300:]))
                        continue
                    with open(hits, "rb") as f:
                        if f.read() != expected:
                            failures.append("{}: hit buffer differs from this CPU's single rays".format(label))
                    print("ok  " + label)
        for cpu, (_, refused, chosen) in CPUS.items():
            for simd, reason in refused.items():
                done, _ = render([qemu, "-cpu", cpu], "bvh", simd, "refused")
                errors = [line for line in done.stderr.splitlines() if not line.startswith("qemu-x86_64: warning")]
                if done.returncode == 0 or len(errors) != 1 or reason not in errors[0]:
                    failures.append("{} --simd {}: expected one line naming {}, got exit {}: {}".format(
                        cpu, simd, reason, done.returncode, errors))
                else:
                    print("ok  {} --simd {} refused: {}".format(cpu, simd, errors[0]))
            done = run([qemu, "-cpu", cpu, trident, "cpu"])
            if done.returncode != 0 or chosen not in done.stdout:
                failures.append("{}: trident cpu should say '{}': {}".format(cpu, chosen, done.stdout.strip()))
    for failure in failures:
        print("FAIL " + failure)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
