#!/usr/bin/python3
"""No code beyond x86-64-v2 outside the 8- and 16-lane kernels of a portable build.

    /usr/bin/python3 tests/app/check_isa_leaks.py BINARY...

A portable build compiles its baseline for x86-64-v2 and its kernel files again for x86-64-v3 and
-v4 (simd/README.md). An inline function that a kernel file and a baseline file both emit is one
COMDAT symbol, and the linker keeps one copy for every caller: were it the kernel file's, baseline
code would run AVX instructions and fault on an SSE4.2 CPU. So every global or weak function whose
code needs more than x86-64-v2 (a VEX or EVEX instruction, BMI1/2, LZCNT, MOVBE, an AVX-512 mask
instruction) must name its architecture: xsimd's avx2 or avx512 tag, or SimdWidth 8 or 16 lanes
(RenderKernels<Structure, SimdWidth::w8>). Local functions (a kernel file's own clones) can only be
called from their own file, and are left out. TZCNT is left out too: GCC emits `rep bsf` for
__builtin_ctz on any CPU, which objdump prints as tzcnt and an older CPU runs as BSF.
Exit 1 with the offending functions listed, 0 when there are none.
"""
import re
import subprocess
import sys

BEYOND_V2 = re.compile(r"^\s*[0-9a-f]+:\s+(v[a-z0-9]+|andn|bextr|blsi|blsmsk|blsr|bzhi|mulx|pdep|pext|rorx|"
                       r"sarx|shlx|shrx|lzcnt|movbe|k[a-z]+[bwdq])\s")
FUNCTION = re.compile(r"^([0-9a-f]+) <(.*)>:$")
# SimdWidth's enumerators print as numbers: scalar 0, w4 1, w8 2, w16 3.
WIDE_ARCH = re.compile(r"avx2|avx512|\(trident::SimdWidth\)[23]\b")


def exported_addresses(binary):
    """Addresses of the global and weak functions (nm's T, W and i)."""
    out = subprocess.run(["nm", "--defined-only", binary], capture_output=True, text=True, check=True).stdout
    return {int(f[0], 16) for f in (line.split() for line in out.splitlines()) if len(f) >= 3 and f[1] in "TWi"}


def leaks(binary):
    exported = exported_addresses(binary)
    dump = subprocess.Popen(["objdump", "-d", "-C", "--no-show-raw-insn", binary], stdout=subprocess.PIPE,
                            text=True)
    found, checked, name, watch = {}, 0, None, False
    for line in dump.stdout:
        m = FUNCTION.match(line)
        if m:
            name = m.group(2)
            watch = int(m.group(1), 16) in exported and not WIDE_ARCH.search(name)
            checked += watch
            continue
        if watch and name not in found:
            i = BEYOND_V2.match(line)
            if i:
                found[name] = i.group(1)
    if dump.wait() != 0:
        sys.exit("check_isa_leaks.py: objdump failed on {}".format(binary))
    return checked, found


def main():
    if len(sys.argv) < 2:
        sys.exit("usage: check_isa_leaks.py BINARY...")
    failed = False
    for binary in sys.argv[1:]:
        checked, found = leaks(binary)
        if checked == 0:
            sys.exit("check_isa_leaks.py: {}: no global function found to check (stripped?)".format(binary))
        print("{}: {} global functions outside the wide kernels, {} with code beyond x86-64-v2".format(
            binary, checked, len(found)))
        for name, instruction in sorted(found.items()):
            print("  {}  {}".format(instruction, name[:300]))
        failed |= bool(found)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
