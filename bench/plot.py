#!/usr/bin/env python3
"""Charts from trident-bench's JSON (--json FILE), written as PNGs into a folder.

    python3 bench/plot.py results.json --out charts/ [--rays primary|shadow|diffuse]

Always: build time and Mrays/s per scene and structure (the reference study's Figures 17 and 18,
grouped bars), each structure's fastest traversal per scene (the study's question, bars labelled
with the traversal) and speed against error (scatter). When the run has them: scalar against SIMD
traversals, thread scaling, and the sweep chart of a --sweep run (Figure 16 for octree-depth).
`--rays shadow` or `diffuse` charts that ray kind's rows instead of the primary rays': Mrays/s,
the fastest traversal and scalar against SIMD (build time and error are the primary rows').
Needs only python3 and Debian's python3-matplotlib; draws with the Agg backend (no display).
"""
import argparse
import json
import os
import sys

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    sys.exit("plot.py: matplotlib is missing (Debian: apt-get install python3-matplotlib)")

# The row helpers the Markdown summaries use too (bench/summarize.py, standard library only).
from summarize import EMBREE_CALL, LABELS, ordered, scenes_in_order

STRUCTURE_ORDER = ["bvh", "kdtree", "octree", "brute", "embree"]


def headline_rows(report):
    """Rows at the run's largest thread count, single rays (Embree: rtcIntersect1 or rtcOccluded1)."""
    threads = max(report["threads"])
    rows = [r for r in report["rows"] if r["threads"] == threads and r["sweep_value"] is None]
    return [r for r in rows if r["traversal"] == "scalar" or
            (r["structure"] == "embree" and r["traversal"] in (EMBREE_CALL["scalar"], "rtcOccluded1"))], threads


def subtitle(report, threads):
    return "{}, {} threads, {}x{}, median of {}".format(
        report["machine"]["cpu"], threads, report["width"], report["height"], report["repeats"])


def log_scale_if_wide(ax, values):
    """A log y axis when the figures span more than two orders of magnitude (brute force beside trees)."""
    values = [v for v in values if v]
    if values and max(values) / min(values) > 100:
        ax.set_yscale("log")


def grouped_bars(ax, scenes, series, value_of):
    """series: list of (label, rows); bars of each series side by side per scene."""
    width = 0.8 / max(1, len(series))
    for i, (label, rows) in enumerate(series):
        by_scene = {r["scene"]: value_of(r) for r in rows}
        xs = [k + (i - (len(series) - 1) / 2) * width for k in range(len(scenes))]
        ax.bar(xs, [by_scene.get(s, 0) or 0 for s in scenes], width, label=label)
    ax.set_xticks(range(len(scenes)))
    ax.set_xticklabels(scenes, rotation=20)
    log_scale_if_wide(ax, [value_of(r) for _, rows in series for r in rows])
    ax.legend()
    ax.grid(axis="y", alpha=0.3)


def save(fig, out_dir, name, written):
    path = os.path.join(out_dir, name)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    written.append(path)


def per_structure_chart(report, out_dir, written, name, ylabel, title, value_of):
    rows, threads = headline_rows(report)
    if not rows:
        return
    scenes = scenes_in_order(rows)
    series = [(LABELS.get(s, s), [r for r in rows if r["structure"] == s])
              for s in ordered([r["structure"] for r in rows], STRUCTURE_ORDER)]
    fig, ax = plt.subplots(figsize=(9, 5))
    grouped_bars(ax, scenes, series, value_of)
    ax.set_ylabel(ylabel)
    ax.set_title("{}\n{}".format(title, subtitle(report, threads)), fontsize=10)
    save(fig, out_dir, name, written)


def fastest_chart(report, out_dir, written, kind):
    """Per scene, each structure's fastest traversal at the run's largest thread count, labelled."""
    threads = max(report["threads"])
    best = {}
    for r in report["rows"]:
        if r["threads"] != threads or r["sweep_value"] is not None or r["mrays_per_s"] is None:
            continue
        key = (r["scene"], r["structure"])
        if key not in best or r["mrays_per_s"] > best[key]["mrays_per_s"]:
            best[key] = r
    if not best:
        return
    scenes = scenes_in_order(list(best.values()))
    structures = ordered([s for _, s in best], STRUCTURE_ORDER)
    width = 0.8 / len(structures)
    fig, ax = plt.subplots(figsize=(max(9, len(scenes) * 1.6), 5))
    for i, structure in enumerate(structures):
        xs = [k + (i - (len(structures) - 1) / 2) * width for k in range(len(scenes))]
        rows = [best.get((scene, structure)) for scene in scenes]
        ax.bar(xs, [r["mrays_per_s"] if r else 0 for r in rows], width, label=LABELS.get(structure, structure))
        for x, r in zip(xs, rows):
            if r:
                ax.text(x, r["mrays_per_s"], r["traversal"], ha="center", va="bottom", rotation=90, fontsize=7)
    ax.set_xticks(range(len(scenes)))
    ax.set_xticklabels(scenes, rotation=20)
    log_scale_if_wide(ax, [r["mrays_per_s"] for r in best.values()])
    low, high = ax.get_ylim()  # room above the bars for their labels
    ax.set_ylim(low, high * (4 if ax.get_yscale() == "log" else 1.3))
    ax.legend()
    ax.grid(axis="y", alpha=0.3)
    ax.set_ylabel("Mrays/s")
    ax.set_title("{} rays: each structure's fastest traversal\n{}".format(kind.capitalize(), subtitle(report, threads)),
                 fontsize=10)
    save(fig, out_dir, "fastest.png", written)


def scalar_vs_simd(report, out_dir, written):
    ours = [r for r in report["rows"] if r["structure"] != "embree" and r["sweep_value"] is None]
    traversals = ordered([r["traversal"] for r in ours], list(EMBREE_CALL))
    if len(traversals) < 2:
        return
    threads = max(report["threads"])
    ours = [r for r in ours if r["threads"] == threads]
    groups = []
    for r in ours:
        key = "{}\n{}".format(r["scene"], LABELS.get(r["structure"], r["structure"]))
        if key not in groups:
            groups.append(key)
    series = []
    for t in traversals:
        rows = [dict(r, scene="{}\n{}".format(r["scene"], LABELS.get(r["structure"], r["structure"])))
                for r in ours if r["traversal"] == t]
        series.append((t, rows))
    fig, ax = plt.subplots(figsize=(max(8, len(groups) * 1.2), 5))
    grouped_bars(ax, groups, series, lambda r: r["mrays_per_s"])
    ax.set_ylabel("Mrays/s")
    ax.set_title("Scalar against SIMD traversal\n{}".format(subtitle(report, threads)), fontsize=10)
    save(fig, out_dir, "scalar_vs_simd.png", written)


def thread_scaling(report, out_dir, written):
    if len(set(report["threads"])) < 2:
        return
    rows = [r for r in report["rows"] if r["sweep_value"] is None and r["traversal"] in ("scalar", "rtcIntersect1")]
    if not rows:
        return
    fig, ax = plt.subplots(figsize=(8, 5))
    for scene in scenes_in_order(rows):
        for s in ordered([r["structure"] for r in rows if r["scene"] == scene], STRUCTURE_ORDER):
            points = sorted((r["threads"], r["mrays_per_s"]) for r in rows if r["scene"] == scene and r["structure"] == s)
            ax.plot([p[0] for p in points], [p[1] for p in points], marker="o",
                    label="{} {}".format(scene, LABELS.get(s, s)))
    log_scale_if_wide(ax, [r["mrays_per_s"] for r in rows])
    ax.set_xlabel("threads")
    ax.set_ylabel("Mrays/s")
    ax.set_xticks(sorted(set(report["threads"])))
    ax.set_title("Thread scaling (scalar; Embree rtcIntersect1), {}x{}".format(report["width"], report["height"]),
                 fontsize=10)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    save(fig, out_dir, "thread_scaling.png", written)


VARIANT_MARKERS = {("watertight", "robust"): "o", ("watertight", "fast"): "s",
                   ("moller_trumbore", "robust"): "^", ("moller_trumbore", "fast"): "v"}


def speed_vs_error(report, out_dir, written):
    # Colour says the structure, the marker the variant (triangle test, slab test), so one run with
    # --triangle-test and --slabs lists shows what being exact costs.
    rows = [r for r in report["rows"] if r["hit_miss_share"] is not None and r["structure"] != "embree"]
    if not rows:
        return
    fig, ax = plt.subplots(figsize=(8, 5))
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    structures = ordered([r["structure"] for r in rows], STRUCTURE_ORDER)
    variants = sorted({(r["triangle_test"], r["slabs"]) for r in rows}, key=lambda v: list(VARIANT_MARKERS).index(v)
                      if v in VARIANT_MARKERS else len(VARIANT_MARKERS))
    for i, s in enumerate(structures):
        for v in variants:
            mine = [r for r in rows if r["structure"] == s and (r["triangle_test"], r["slabs"]) == v]
            if mine:
                ax.scatter([100.0 * (r["hit_miss_share"] + r["triangle_share"]) for r in mine],
                           [r["mrays_per_s"] for r in mine], color=colours[i % len(colours)],
                           marker=VARIANT_MARKERS.get(v, "x"), alpha=0.8,
                           label="{} {}/{}".format(LABELS.get(s, s), v[0], v[1]))
    ax.set_xscale("symlog", linthresh=1e-3)
    ax.set_xlim(left=0)
    log_scale_if_wide(ax, [r["mrays_per_s"] for r in rows])
    ax.set_xlabel("rays disagreeing with the reference (hit/miss or triangle), %")
    ax.set_ylabel("Mrays/s")
    ax.set_title("Speed against error, every scene and traversal\nreference: {}".format(report["reference"]),
                 fontsize=9)
    ax.legend(fontsize=7, ncol=2 if len(variants) > 1 else 1)
    ax.grid(alpha=0.3)
    save(fig, out_dir, "speed_vs_error.png", written)


def sweep_chart(report, out_dir, written, name):
    sweep = report.get("sweep")
    if not sweep:
        return
    rows = [r for r in report["rows"] if r["sweep_value"] is not None]
    threads = max(report["threads"])
    rows = [r for r in rows if r["threads"] == threads and r["traversal"] == "scalar"]
    fig, (build_ax, render_ax) = plt.subplots(1, 2, figsize=(11, 4.5))
    for scene in scenes_in_order(rows):
        points = sorted((r["sweep_value"], r["build_ms"], r["render_ms"]) for r in rows if r["scene"] == scene)
        xs = [p[0] for p in points]
        build_ax.plot(xs, [p[1] for p in points], marker="o", label=scene)
        render_ax.plot(xs, [p[2] for p in points], marker="o", label=scene)
    for ax, what in ((build_ax, "build ms"), (render_ax, "render ms")):
        ax.set_xlabel(sweep["parameter"])
        ax.set_ylabel(what)
        ax.set_yscale("log")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle("Sweep {} ({} threads, {}x{})".format(sweep["name"], threads, report["width"], report["height"]),
                 fontsize=10)
    save(fig, out_dir, name, written)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("json", help="trident-bench --json output")
    parser.add_argument("--out", default="charts", help="folder for the PNGs (default: charts)")
    parser.add_argument("--rays", default="primary", choices=("primary", "shadow", "diffuse"),
                        help="the ray kind to chart (default primary)")
    args = parser.parse_args()
    try:
        with open(args.json) as f:
            report = json.load(f)
    except (OSError, ValueError) as e:
        sys.exit("plot.py: {}: {}".format(args.json, e))
    report["rows"] = [r for r in report.get("rows", []) if r.get("rays", "primary") == args.rays]
    if not report["rows"]:
        sys.exit("plot.py: {}: no rows of {} rays".format(args.json, args.rays))
    os.makedirs(args.out, exist_ok=True)
    written = []
    if args.rays == "primary":
        per_structure_chart(report, args.out, written, "build_time.png", "build time, ms",
                            "Build time per scene and structure (study Figure 17)", lambda r: r["build_ms"])
    per_structure_chart(report, args.out, written, "mrays.png", "Mrays/s",
                        "{} rays per second per scene and structure{}".format(
                            args.rays.capitalize(), " (study Figure 18)" if args.rays == "primary" else ""),
                        lambda r: r["mrays_per_s"])
    fastest_chart(report, args.out, written, args.rays)
    scalar_vs_simd(report, args.out, written)
    if args.rays == "primary":
        thread_scaling(report, args.out, written)
        speed_vs_error(report, args.out, written)
        # A sweep's chart is sweep_NAME.png, or its JSON's name when that starts with sweep_ too, so
        # two runs of one sweep on different scenes (sweep_octree-depth_small, _large) keep both.
        stem = os.path.splitext(os.path.basename(args.json))[0]
        sweep = report.get("sweep") or {}
        sweep_chart(report, args.out, written,
                    stem + ".png" if stem.startswith("sweep_") else "sweep_{}.png".format(sweep.get("name")))
    for path in written:
        print(path)


if __name__ == "__main__":
    main()
