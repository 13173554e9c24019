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
RENDER = ["render", "teapot", "--width", "32", "--height", "20", "--threads", "1"]


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
        def render(prefix, structure, simd, name):
            hits = os.path.join(scratch, name + ".hits")
            done = run(prefix + [trident] + RENDER + ["--accel", structure, "--simd", simd, "--output",
                                                     os.path.join(scratch, "image.png"), "--dump-hits", hits])
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
