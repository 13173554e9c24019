#!/usr/bin/env bash
# The trials' runs: bench/reproduce.sh as it was on 2026-12-01, when RESULTS.md held every trial
# (about 80 minutes on 2 cores). It re-measures the outputs in data/ and the charts in charts/ (the
# study run, the structures and paired runs, scaling, Embree's binned builder, the ray kinds, the
# variants, the stress suite and the sweeps); only its output folders changed, so that it leaves
# the current run set in bench/results/ alone. Run from the repository root after `bash run.sh
# test` (or any Release build in build/), with ../shared beside the repository and nothing else
# running. The trials' summary tables are printed from its JSON by bench/summarize.py.
set -euo pipefail
bench=build/trident-bench
scenes=../shared/scenes/scenes.json
out=bench/experiments/data
python=/usr/bin/python3  # Debian's, which has matplotlib
mkdir -p "$out" bench/experiments/charts

# Study Table 2: every structure, scalar and each packet width, 1 and 2 threads, Embree beside.
$bench --scenes $scenes --simd scalar,simd4,simd8,simd16 --threads 1,2 --embree 1,4,8,16 \
    --json $out/study.json --markdown $out/study.md --csv $out/study.csv

# The three structures side by side, scalar and 8 and 16 lanes, 1 and 2 threads, without Embree:
# the KD-tree's and the Octree's speed relative to the BVH's (issues 4 and 6).
$bench --scenes $scenes --accel bvh,kdtree,octree --simd scalar,simd8,simd16 --threads 1,2 --embree none \
    --reference self --json $out/structures.json --markdown $out/structures.md

# The issues' ratios in pairs (issues 4 and 6): each primary render followed by the same structure's
# scalar render, the BVH's at the same traversal and Embree's call of the same width, on the same rays.
$bench --scenes $scenes --accel bvh,kdtree,octree --simd scalar,simd8,simd16 --threads 1,2 --embree none \
    --reference self --paired scalar,bvh,embree --json $out/paired.json --markdown $out/paired.md --csv $out/paired.csv

# Two threads over one from paired runs: each 2-thread render timed again on one thread right after.
$bench --scenes $scenes --accel bvh,kdtree,octree --simd scalar --threads 2 --scaling --embree 1 \
    --json $out/scaling.json --markdown $out/scaling.md --csv $out/scaling.csv

# Our BVH against Embree's binned SAH builder (RTC_BUILD_QUALITY_MEDIUM, no spatial splits), one
# thread: build time like for like (issue 3), and Embree's tracing on a tree without spatial splits.
$bench --scenes $scenes --accel bvh --simd scalar,simd8,simd16 --threads 1 --embree 1,8,16 --embree-quality medium \
    --reference self --json $out/embree_medium.json --markdown $out/embree_medium.md

# Shadow and diffuse rays beside primary (issue 9), 2 threads.
$bench --scenes $scenes --rays primary,shadow,diffuse --simd scalar,simd8,simd16 --threads 2 --embree 1,8,16 \
    --json $out/ray_kinds.json --markdown $out/ray_kinds.md --csv $out/ray_kinds.csv

# Speed against error: both triangle tests and both slab tests, at half resolution; 9 repeats, as
# the short Teapot runs are the noisiest.
$bench --scenes $scenes --triangle-test watertight,moller_trumbore --slabs robust,fast --simd scalar,simd16 \
    --threads 2 --embree 1 --width 960 --height 540 --repeats 9 \
    --json $out/variants.json --markdown $out/variants.md --csv $out/variants.csv

# The stress suite with the defaults (12M closest-hit and 12M any-hit rays per structure and width),
# then the other three variants at 100k rays per case for the speed-against-error table. A variant
# that loses hits exits 1; that is the figure being measured, so it does not stop this script.
build/trident stress --json $out/stress_default.json > $out/stress_default.txt || true
for variant in "watertight fast" "moller_trumbore robust" "moller_trumbore fast"; do
    set -- $variant
    build/trident stress --rays 100000 --triangle-test $1 --slabs $2 --json $out/stress_$1_$2.json \
        > $out/stress_$1_$2.txt || true
done

# Sweeps on the built-in scenes (the study's Figure 16 for the octree depth). A depth of 1 or 2 on
# the million-triangle hall and city is close to brute force, so those two get a smaller image.
sweep() {  # name, output suffix, then extra options
    local name=$1 suffix=$2; shift 2
    $bench --sweep "$name" --repeats 5 --threads 2 --embree none --quiet "$@" \
        --json $out/sweep_$suffix.json --markdown $out/sweep_$suffix.md --csv $out/sweep_$suffix.csv
    $python bench/plot.py $out/sweep_$suffix.json --out bench/experiments/charts/sweeps
}
sweep octree-depth octree-depth_small --only teapot,asteroid --width 320 --height 180
sweep octree-depth octree-depth_large --only hall,city --width 96 --height 54
for name in bvh-buckets bvh-cost kd-cost kd-empty-bonus; do
    sweep $name $name --width 640 --height 360
done
# Perfect splits on the study's scenes, where large triangles straddle many cells (Room).
sweep kd-perfect-splits kd-perfect-splits --scenes $scenes --width 960 --height 540
# The KD-tree's depth limit (pbrt's round(8 + 1.3 log2 N)) on the study's scenes, one thread:
# whether the limit stops the trees of the million-triangle scans early.
$bench --sweep kd-depth --scenes $scenes --simd scalar,simd16 --repeats 7 --threads 1 --embree none --quiet \
    --width 960 --height 540 --json $out/sweep_kd-depth.json --markdown $out/sweep_kd-depth.md \
    --csv $out/sweep_kd-depth.csv
$python bench/plot.py $out/sweep_kd-depth.json --out bench/experiments/charts/sweeps

# Charts of the main runs last (each run of plot.py rewrites the charts its input has).
$python bench/plot.py $out/variants.json --out bench/experiments/charts/variants
$python bench/plot.py $out/study.json --out bench/experiments/charts
