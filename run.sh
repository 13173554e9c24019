#!/usr/bin/env bash
# trident's one entry point for a fresh Debian 12 machine (run as root, or with sudo available):
#   bash run.sh bench   install what is missing, build (native), run the benchmark on the built-in scenes
#   bash run.sh test    install what is missing, build (Release, portable; ASan+UBSan, native), run every test
#                       (the Python module's pytest with Debian's /usr/bin/python3, in the Release build)
# Extra arguments after the command are passed to the benchmark (bench) or to ctest (test).
set -euo pipefail
cd "$(dirname "$0")"

command_name="${1:-}"
shift || true
jobs="$(nproc 2>/dev/null || echo 2)"

packages=(build-essential cmake ninja-build pkg-config git
          libxsimd-dev libtbb-dev libtinyobjloader-dev libstb-dev doctest-dev
          libcli11-dev nlohmann-json3-dev libfmt-dev libembree-dev python3 python3-matplotlib
          pybind11-dev python3-pybind11 python3-numpy python3-pytest python3-dev)
# Wanted by one test, not needed to build: qemu-x86_64 runs the portable build as older CPUs
# (tests/app/test_emulated_cpus.py). Where it cannot be installed, CMake leaves that test out.
optional_packages=(qemu-user)

missing_of() {  # the packages named that are not installed
    for p in "$@"; do
        dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || echo "$p"
    done
}

install_missing() {
    local missing optional sudo=""
    mapfile -t missing < <(missing_of "${packages[@]}")
    mapfile -t optional < <(missing_of "${optional_packages[@]}")
    if [ "${#missing[@]}" -eq 0 ] && [ "${#optional[@]}" -eq 0 ]; then
        echo "run.sh: all packages present"
        return
    fi
    [ "$(id -u)" -eq 0 ] || sudo="sudo"
    $sudo apt-get update -qq || [ "${#missing[@]}" -eq 0 ]
    if [ "${#missing[@]}" -gt 0 ]; then
        echo "run.sh: installing ${missing[*]}"
        DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
    fi
    if [ "${#optional[@]}" -gt 0 ]; then
        echo "run.sh: installing ${optional[*]} (optional)"
        DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${optional[@]}" ||
            echo "run.sh: ${optional[*]} could not be installed; the tests that need it are left out"
    fi
}

build() {  # build DIR [cmake args...]; only the targets in $targets when it is set
    local dir="$1"
    shift
    cmake -S . -B "$dir" -G Ninja "$@" >/dev/null
    cmake --build "$dir" -j "$jobs" ${targets:+--target $targets}
}

case "$command_name" in
    bench)
        install_missing
        # The benchmark measures this machine: a native build (-march=native) of the benchmark alone,
        # neither the CLI, the test executables nor the sanitizer build.
        targets="trident-bench" build build-native -DCMAKE_BUILD_TYPE=Release -DTRIDENT_MARCH=native
        # Without arguments: the built-in scenes, scalar against the widest SIMD packets, Embree beside.
        [ "$#" -gt 0 ] || set -- --simd scalar,auto --json build-native/bench.json --markdown build-native/bench.md
        build-native/trident-bench "$@"
        ;;
    test)
        install_missing
        # The Release build is the portable one users get (TRIDENT_MARCH=portable: an x86-64-v2
        # baseline, kernels for SSE4.2, AVX2 and AVX-512 chosen at run time), so its tests cover the
        # dispatch, every ISA cap, no AVX code outside the kernels (isa_leaks) and runs as an SSE4.2
        # and an AVX2 CPU under qemu (emulated_cpus).
        build build -DCMAKE_BUILD_TYPE=Release -DTRIDENT_MARCH=portable
        (cd build && ctest --output-on-failure -j "$jobs" "$@")
        # The sanitizer build runs the same tests with AddressSanitizer and UndefinedBehaviorSanitizer,
        # compiled for this machine as the benchmark is.
        build build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTRIDENT_SANITIZE=ON -DTRIDENT_MARCH=native
        (cd build-asan && ctest --output-on-failure -j "$jobs" "$@")
        ;;
    *)
        echo "usage: bash run.sh bench|test [args]" >&2
        exit 2
        ;;
esac
