#!/usr/bin/env bash
# How long the README's two commands take for a newcomer: `bash run.sh test` and `bash run.sh bench`,
# each from a clean clone of this commit (packages installed, no build folders) with ../shared beside
# it, as CI has it. Writes their wall-clock seconds and the machine as JSON (bench/RESULTS.md shows
# them; bench/reproduce.sh runs this as its `setup` step). Nothing else may run meanwhile.
#
#     bash bench/time_setup.sh OUT.json
set -euo pipefail
cd "$(dirname "$0")/.."
out=$(realpath -m "${1:?usage: bash bench/time_setup.sh OUT.json}")
if [[ ! -d ../shared ]]; then
    echo "time_setup.sh: ../shared is missing: it must sit beside the repository" >&2
    exit 1
fi
shared=$(realpath ../shared)
commit=$(git rev-parse --short HEAD)
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
ln -s "$shared" "$scratch/shared"

# seconds COMMAND: a fresh clone of HEAD runs `bash run.sh COMMAND`; prints its wall-clock seconds.
seconds() {
    local clone="$scratch/trident-$1" log="$scratch/$1.log"
    rm -rf "$clone"
    git clone -q . "$clone"
    local start=$SECONDS
    if ! (cd "$clone" && bash run.sh "$1") > "$log" 2>&1; then
        tail -20 "$log" >&2
        echo "time_setup.sh: bash run.sh $1 failed in a clean clone of $commit (its log's end above)" >&2
        exit 1
    fi
    echo $((SECONDS - start))
    rm -rf "$clone"
}
test_seconds=$(seconds test)
bench_seconds=$(seconds bench)

cpu=$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo | head -1)
/usr/bin/python3 - "$out" "$commit" "$test_seconds" "$bench_seconds" "$cpu" "$(nproc)" <<'EOF'
import json, sys
out, commit, test_seconds, bench_seconds, cpu, cores = sys.argv[1:]
with open(out, "w") as f:
    json.dump({"commit": commit, "cpu": cpu, "hardware_threads": int(cores),
               "commands": [{"command": "bash run.sh test", "seconds": int(test_seconds)},
                            {"command": "bash run.sh bench", "seconds": int(bench_seconds)}]}, f, indent=2)
    f.write("\n")
EOF
echo "time_setup.sh: run.sh test ${test_seconds} s, run.sh bench ${bench_seconds} s (clean clones of $commit)" >&2
