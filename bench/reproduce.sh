#!/usr/bin/env bash
# The run set behind bench/RESULTS.md: every table and chart of it, measured on this machine at
# this commit, then the page generated from the JSON (bench/summarize.py page). About 70 minutes on
# 2 cores (an estimate from the rows and the resolution; each step prints how long it took, and the
# page lists the times). Run from anywhere, with ../shared beside the repository and nothing else
# running on the machine:
#
#     bash bench/reproduce.sh            # the run set: bench/results/*.json, bench/charts, bench/RESULTS.md
#     bash bench/reproduce.sh --quick    # the same steps on two scenes at 160x90, one repeat (a few
#                                        # minutes): checks the script and the page; figures meaningless
#
# What each step measures:
#   primary    the study's seven scenes at 1920x1080, every structure, single rays and 8- and 16-lane
#              packets, 1 and 2 threads, Embree's rtcIntersect1/8/16 rows beside them, and every row
#              paired with its single rays, the BVH and Embree on the same rays (--paired): Table 2,
#              ours against Embree, build time, memory, error, the study's question for primary rays.
#              Our rows skip the image tiles that see nothing, as the renderer does (--tile-culling).
#   ray_kinds  primary, shadow and diffuse rays of the same scenes at 960x540 (a quarter of the rays:
#              the diffuse rows are the run's slowest), the same traversals, threads and Embree calls:
#              the study's question per ray kind, shadow and diffuse rays against Embree, and shadow
#              rays' any hit against closest hit (--paired closest).
#   spatial    the wide BVH with spatial splits (--bvh-builder spatial) and Embree's high-quality build,
#              one thread, the study's seven scenes: their build times.
#   binned     the wide and the binary BVH without spatial splits (--bvh-builder binned), Embree beside,
#              one thread: the build times of the binned build, which the default (auto) gives only
#              the scenes without large triangles.
#   portable   the portable build (build-portable/, what `run.sh test` and users get) against this
#              native one on the same rays, in pairs seconds apart (bench/compare_builds.py): the
#              built-in scenes, every structure, width and ray kind, one thread.
#   portable_self  the same with the native build on both sides (Teapot and Asteroid): the method's noise.
#   avx2       the portable build under TRIDENT_ISA=avx2 (the kernels of a CPU without AVX-512, such as
#              the study's Ryzen) against Embree limited to AVX2, the study's scenes at 960x540, wide BVH
#              single rays and 8-lane packets, every ray kind, one thread, paired.
#   caps       the portable build's primary-ray hit buffers under every ISA cap the CPU runs, every
#              structure and width the cap allows, byte for byte against its uncapped single rays'
#              (bench/compare_caps.py), the study's scenes at 1920x1080.
#   python     the Python module's scene.intersect on camera_rays against trident-bench's render of the
#              same rays, same structure and traversal, two threads, in pairs (bench/python_bench.py).
#   setup      `bash run.sh test` and `bash run.sh bench`, each from a clean clone of this commit
#              (bench/time_setup.sh): what a newcomer waits, on this machine.
# The trials behind the figures (older runs, other machines, sweeps) are in bench/experiments/.
set -euo pipefail
cd "$(dirname "$0")/.."
bench=build-native/trident-bench
scenes=../shared/scenes/scenes.json
out=bench/results
charts=bench/charts
python=/usr/bin/python3  # Debian's, which has matplotlib

only=() repeats=() primary_size=(--width 1920 --height 1080) secondary_size=(--width 960 --height 540)
portable_scenes=teapot,asteroid,hall portable_self_scenes=teapot,asteroid portable_rounds=3
portable_size=(--width 640 --height 360) setup=yes
python_args=(--rounds 5)
placeholder=""
case "${1:-}" in
    "") ;;
    --quick)
        only=(--only teapot,sponza) repeats=(--repeats 1)
        primary_size=(--width 160 --height 90) secondary_size=(--width 160 --height 90)
        portable_scenes=teapot portable_self_scenes=teapot portable_rounds=1
        portable_size=(--width 160 --height 90) setup=""
        python_args=(--only teapot,sponza --width 160 --height 90 --rounds 1 --repeats 1)
        placeholder="Made by \`bash bench/reproduce.sh --quick\` (Teapot and Sponza at 160x90, one timed run each)."
        ;;
    --only)
        # The full settings on a few scenes, for a run set that must fit a short window.
        only=(--only "${2:?--only needs a comma-separated list of scenes}") python_args+=(--only "$2")
        placeholder="Made by \`bash bench/reproduce.sh --only $2\`: the full settings on these scenes only."
        ;;
    *) echo "reproduce.sh: unknown option '$1' (expected nothing, --quick or --only SCENES)" >&2; exit 2 ;;
esac
if [[ ! -f $scenes ]]; then
    echo "reproduce.sh: $scenes is missing: ../shared must sit beside the repository" >&2
    exit 1
fi

# step NAME COMMAND...: runs it with its standard output in $logs/NAME.out (trident-bench's tables
# are in its --markdown file too), prints and records how long it took (the page lists it).
logs=$(mktemp -d)
trap 'rm -rf "$logs"' EXIT
step() {
    local name=$1 start=$SECONDS
    shift
    echo "== $name: $*" >&2
    "$@" > "$logs/$name.out"
    local seconds=$((SECONDS - start))
    echo "== $name: $seconds s" >&2
    printf '%s\t%s\t%s\n' "$name" "$seconds" "$*" >> "$logs/steps.tsv"
}

# The binary measured is built from this tree for this machine, as `run.sh bench` builds it (Release,
# -march=native: the figures are this CPU's; the portable build's cost is in experiments/portable_build.md).
cmake -S . -B build-native -G Ninja -DCMAKE_BUILD_TYPE=Release -DTRIDENT_MARCH=native > /dev/null
cmake --build build-native -j2 --target trident-bench trident_python > /dev/null
cmake -S . -B build-portable -G Ninja -DCMAKE_BUILD_TYPE=Release -DTRIDENT_MARCH=portable > /dev/null
cmake --build build-portable -j2 --target trident-bench > /dev/null
commit=$(git rev-parse --short HEAD)
# Uncommitted changes outside what the run writes and the trials' notes (which no binary reads).
dirty=$(git status --porcelain --untracked-files=no -- . ':!bench/results' ':!bench/charts' ':!bench/RESULTS.md' \
    ':!bench/experiments' | head -c 1 | wc -c)
date=$(date -u +%Y-%m-%dT%H:%M:%SZ)

# The run set replaces the last one whole: no file of an older run stays beside it.
rm -rf "$out" "$charts"
mkdir -p "$out" "$charts"
# First the clean-clone times: the step that builds and tests everything, so a failure costs the
# least of the run.
if [[ -n $setup ]]; then
    step setup bash bench/time_setup.sh $out/setup.json
fi
step primary $bench --scenes $scenes "${only[@]}" --rays primary --simd scalar,simd8,simd16 --threads 1,2 \
    --embree 1,8,16 --paired scalar,bvh,embree "${primary_size[@]}" "${repeats[@]}" --quiet \
    --json $out/primary.json --markdown $out/primary.md --csv $out/primary.csv
step ray_kinds $bench --scenes $scenes "${only[@]}" --rays primary,shadow,diffuse --simd scalar,simd8,simd16 \
    --threads 1,2 --embree 1,8,16 --paired bvh,embree,closest "${secondary_size[@]}" "${repeats[@]}" --quiet \
    --json $out/ray_kinds.json --markdown $out/ray_kinds.md --csv $out/ray_kinds.csv
# The wide BVH built with spatial splits (--bvh-builder spatial, the higher-quality option) beside
# Embree's high-quality build, one thread: issue 31's build-time target for it. Build times only,
# so a small image.
step spatial $bench --scenes $scenes "${only[@]}" --accel bvh --bvh-builder spatial --rays primary --simd scalar \
    --threads 1 --embree 1 --width 320 --height 180 "${repeats[@]}" --quiet --json $out/spatial.json \
    --csv $out/spatial.csv
# Both BVHs without spatial splits (--bvh-builder binned): the build-time targets of the binned build
# (issues 3 and 31), whatever the default picks per scene.
step binned $bench --scenes $scenes "${only[@]}" --accel bvh,bvh2 --bvh-builder binned --rays primary --simd scalar \
    --threads 1 --embree 1 --width 320 --height 180 "${repeats[@]}" --quiet --json $out/binned.json \
    --csv $out/binned.csv
# The rows both portable steps time (after --each-scene): every structure, width and ray kind.
portable_rows=(--each-accel bvh,bvh2,kdtree,octree -- --simd scalar,simd4,simd8,simd16 --rays primary,shadow,diffuse
               --threads 1 --embree none "${portable_size[@]}")
step portable $python bench/compare_builds.py build-portable/trident-bench $bench --rounds $portable_rounds \
    --json $out/portable.json --markdown $out/portable.md --each-scene $portable_scenes "${portable_rows[@]}"
# The same method with the native build on both sides: every row's ratio is 1 but for the machine's
# noise, which a row of the step above must be read against (issue 34's 0.97x).
step portable_self $python bench/compare_builds.py $bench $bench --rounds $portable_rounds \
    --json $out/portable_self.json --markdown $out/portable_self.md --each-scene $portable_self_scenes \
    "${portable_rows[@]}"
# AVX2 as users have it (issue 34): the cap gives Embree max_isa=avx2 too.
step avx2 env TRIDENT_ISA=avx2 build-portable/trident-bench --scenes $scenes "${only[@]}" --accel bvh \
    --rays primary,shadow,diffuse --simd scalar,simd8 --threads 1 --embree 1,8 --paired embree "${secondary_size[@]}" \
    "${repeats[@]}" --quiet --json $out/avx2.json --csv $out/avx2.csv
# The same hits whichever kernels run (issue 34).
step caps $python bench/compare_caps.py build-portable/trident-bench --json $out/caps.json -- --scenes $scenes \
    "${only[@]}" --accel bvh,bvh2,kdtree,octree --threads 2 "${primary_size[@]}"
# The Python module against the C++ renderer on the same rays (issue 33), both from build-native.
step python env PYTHONPATH=build-native/python $python bench/python_bench.py --bench $bench --scenes $scenes \
    --accel bvh,kdtree,octree --simd scalar,simd8,simd16 --threads 2 --repeats 3 "${python_args[@]}" \
    --json $out/python.json
# Charts: the study's Figures 17 and 18 and the rest for primary rays, and the fastest traversal
# per structure for each ray kind.
step charts_primary $python bench/plot.py $out/primary.json --out $charts
step charts_shadow $python bench/plot.py $out/ray_kinds.json --rays shadow --out $charts/shadow
step charts_diffuse $python bench/plot.py $out/ray_kinds.json --rays diffuse --out $charts/diffuse

# The manifest the page is generated from: the commit, the steps and their times, the files.
$python - "$logs" "$out/run.json" "$commit" "$dirty" "$date" "$placeholder" <<'EOF'
import json, os, sys
logs, manifest, commit, dirty, date, placeholder = sys.argv[1:]
steps = []
for line in open(os.path.join(logs, "steps.tsv")):
    name, seconds, command = line.rstrip("\n").split("\t")
    steps.append({"name": name, "seconds": int(seconds), "command": command})
titles = {"build_time.png": "build time (Figure 17)", "mrays.png": "Mrays/s (Figure 18)",
          "fastest.png": "fastest traversal per structure", "scalar_vs_simd.png": "scalar against SIMD",
          "thread_scaling.png": "thread scaling", "speed_vs_error.png": "speed against error"}
charts = []
chart_paths = [line.strip() for step in steps if step["name"].startswith("charts_")
               for line in open(os.path.join(logs, step["name"] + ".out")) if line.strip()]
for chart in chart_paths:
    path = os.path.relpath(chart, "bench")
    kind = os.path.basename(os.path.dirname(path))
    title = titles.get(os.path.basename(path), os.path.basename(path))
    charts.append({"title": title + ("" if kind == "charts" else ", " + kind), "path": path})
run = {"commit": commit, "dirty": dirty != "0", "date": date, "steps": steps,
       "runs": [{"name": "primary", "json": "primary.json"}, {"name": "ray_kinds", "json": "ray_kinds.json"},
                {"name": "spatial", "json": "spatial.json"}, {"name": "binned", "json": "binned.json"}],
       "charts": charts}
if os.path.exists(os.path.join(os.path.dirname(manifest), "avx2.json")):
    run["runs"].append({"name": "avx2", "json": "avx2.json"})
for name in ("portable", "portable_self", "setup", "python", "caps"):
    if os.path.exists(os.path.join(os.path.dirname(manifest), name + ".json")):
        run[name] = name + ".json"
if placeholder:
    run["placeholder"] = placeholder
with open(manifest, "w") as f:
    json.dump(run, f, indent=2)
    f.write("\n")
EOF
$python bench/summarize.py page --out bench/RESULTS.md
$python bench/summarize.py check bench/RESULTS.md
echo "reproduce.sh: bench/RESULTS.md written from $out/run.json ($SECONDS s in all)" >&2
