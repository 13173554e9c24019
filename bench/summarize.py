#!/usr/bin/env python3
"""Summary tables for bench/RESULTS.md, in Markdown, from trident-bench and trident stress JSON.

    summarize.py study RESULTS.json [--study-table ../shared/BENCHMARK.md]
    summarize.py variants RESULTS.json
    summarize.py sweep RESULTS.json [RESULTS.json ...]
    summarize.py stress STRESS.json [STRESS.json ...]
    summarize.py ray-kinds RESULTS.json
    summarize.py paired RESULTS.json
    summarize.py page [--run bench/results/run.json] [--out bench/RESULTS.md]
    summarize.py check bench/RESULTS.md [--run bench/results/run.json]

`page` prints the whole of bench/RESULTS.md from one run set of bench/reproduce.sh
(bench/results_page.py); `check` makes it again and exits 1, with the difference, when the file
given differs. Every figure printed is read from the JSON given; the study's own Table 2 is read from
BENCHMARK.md, so the side-by-side table quotes it rather than copying it. Only the standard library
is used, so any python3 runs it.
"""
import argparse
import difflib
import json
import os
import re
import statistics
import sys

STRUCTURES = ("bvh", "kdtree", "octree")
NAMES = {"bvh": "BVH", "kdtree": "KD", "octree": "Octree", "embree": "Embree"}
WIDTHS = ("scalar", "simd4", "simd8", "simd16")
# Names for charts and for RESULTS.md's prose (the summary tables keep the short NAMES).
LABELS = {"bvh": "BVH", "kdtree": "KD-tree", "octree": "Octree", "brute": "brute force", "embree": "Embree"}
EMBREE_CALL = {"scalar": "rtcIntersect1", "simd4": "rtcIntersect4", "simd8": "rtcIntersect8",
               "simd16": "rtcIntersect16"}


def fmt(x, digits=3):
    """A figure with `digits` significant digits, no exponent for the ranges these tables hold."""
    if x is None:
        return "-"
    if x == 0:
        return "0"
    magnitude = abs(x)
    if magnitude >= 10 ** digits:
        return "{:.0f}".format(x)
    decimals = max(0, digits - 1 - int(f"{magnitude:e}".split("e")[1]))
    return "{:.{}f}".format(x, decimals)


def ordered(values, order):
    """The distinct values, those in `order` first and in its order, then the others sorted."""
    return sorted(set(values), key=lambda v: (order.index(v) if v in order else len(order), v))


def table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return "\n".join(lines)


def scenes_in_order(rows):
    seen = []
    for r in rows:
        if r["scene"] not in seen:
            seen.append(r["scene"])
    return seen


class Rows:
    """The primary-ray rows of one report, found by scene, structure, traversal and threads."""

    def __init__(self, report):
        self.report = report
        self.rows = [r for r in report["rows"] if r.get("rays", "primary") == "primary"]
        self.scenes = scenes_in_order(self.rows)
        self.threads = sorted(set(report["threads"]))

    def get(self, scene, structure, traversal, threads, **match):
        for r in self.rows:
            if (r["scene"], r["structure"], r["traversal"], r["threads"]) == (scene, structure, traversal, threads) \
                    and all(r.get(k) == v for k, v in match.items()):
                return r
        return None

    def value(self, key, *args, **match):
        r = self.get(*args, **match)
        return None if r is None else r[key]


def ratio(a, b):
    return None if a is None or b is None or b == 0 else a / b


def read_study_table(path):
    """The reference study's Table 2 from BENCHMARK.md: {scene (lower case): {column: value}}."""
    try:
        with open(path) as f:
            text = f.read()
    except OSError:
        return {}
    section = text.split("## The reference study's results", 1)
    if len(section) < 2:
        return {}
    lines = [l for l in section[1].splitlines() if l.startswith("|")]
    if len(lines) < 3:
        return {}
    header = [c.strip() for c in lines[0].strip("|").split("|")]
    out = {}
    for line in lines[2:]:
        cells = [c.strip() for c in line.strip("|").split("|")]
        out[cells[0].lower()] = dict(zip(header, cells))
    return out


def study(report, study_table_path):
    rows = Rows(report)
    t1, tn = rows.threads[0], rows.threads[-1]
    out = []

    reference = read_study_table(study_table_path)
    if reference:
        out.append("### Table 2 beside the study ({} threads here, 12 in the study; build and render in s)\n"
                   .format(tn))
        out.append("Each cell: the study / ours scalar / ours 16-wide (build: the study / ours).\n")
        body = []
        for scene in rows.scenes:
            ref = reference.get(scene)
            if not ref:
                continue
            cells = [scene, ref.get("triangles", "-")]
            for s in STRUCTURES:
                build = rows.value("build_ms", scene, s, "scalar", tn)
                cells.append("{} / {}".format(ref.get("build " + NAMES[s], "-"),
                                              fmt(None if build is None else build / 1000)))
            for key, scale in (("render", 1e-3), ("Mrays/s", 1.0)):
                for s in STRUCTURES:
                    field = "render_ms" if key == "render" else "mrays_per_s"
                    ours = [rows.value(field, scene, s, w, tn) for w in ("scalar", "simd16")]
                    cells.append("{} / {}".format(ref.get("{} {}".format(key, NAMES[s]), "-"),
                                                  " / ".join(fmt(None if v is None else v * scale) for v in ours)))
            body.append(cells)
        header = ["scene", "triangles"] + ["build " + NAMES[s] for s in STRUCTURES] + \
                 ["render " + NAMES[s] for s in STRUCTURES] + ["Mrays/s " + NAMES[s] for s in STRUCTURES]
        out.append(table(header, body))

    out.append("\n### Build ms, {} thread / {} threads\n".format(t1, tn))
    body = []
    for scene in rows.scenes:
        any_row = next(r for r in rows.rows if r["scene"] == scene)
        cells = [scene, any_row["triangles"]]
        for s in STRUCTURES + ("embree",):
            traversal = "rtcIntersect1" if s == "embree" else "scalar"
            cells += [fmt(rows.value("build_ms", scene, s, traversal, t)) for t in (t1, tn)]
        body.append(cells)
    header = ["scene", "triangles"] + ["{} {}t".format(NAMES[s], t) for s in STRUCTURES + ("embree",) for t in (t1, tn)]
    out.append(table(header, body))

    widths = [w for w in WIDTHS if any(r["traversal"] == w for r in rows.rows)]
    out.append("\n### Mrays/s, {} threads, primary rays ({})\n".format(tn, " / ".join(widths)))
    body = []
    for scene in rows.scenes:
        cells = [scene]
        for s in STRUCTURES + ("embree",):
            cells.append(" / ".join(fmt(rows.value("mrays_per_s", scene, s, EMBREE_CALL[w] if s == "embree" else w, tn))
                                    for w in widths))
        body.append(cells)
    out.append(table(["scene"] + [NAMES[s] for s in STRUCTURES] + ["Embree (same calls)"], body))

    packet_widths = [w for w in ("simd8", "simd16") if w in widths]
    out.append("\n### SIMD over scalar, same run ({}), per thread count\n".format(" / ".join(packet_widths)))
    body = []
    for scene in rows.scenes:
        cells = [scene]
        for s in STRUCTURES:
            for t in (t1, tn):
                scalar = rows.value("mrays_per_s", scene, s, "scalar", t)
                cells.append(" / ".join(fmt(ratio(rows.value("mrays_per_s", scene, s, w, t), scalar), 3)
                                        for w in packet_widths))
        body.append(cells)
    out.append(table(["scene"] + ["{} {}t".format(NAMES[s], t) for s in STRUCTURES for t in (t1, tn)], body))

    if t1 != tn:
        out.append("\n### {} threads over {}, scalar Mrays/s\n".format(tn, t1))
        body = []
        for scene in rows.scenes:
            cells = [scene]
            for s in STRUCTURES + ("embree",):
                traversal = "rtcIntersect1" if s == "embree" else "scalar"
                cells.append(fmt(ratio(rows.value("mrays_per_s", scene, s, traversal, tn),
                                       rows.value("mrays_per_s", scene, s, traversal, t1))))
            body.append(cells)
        out.append(table(["scene"] + [NAMES[s] for s in STRUCTURES] + ["Embree rtcIntersect1"], body))

    if any(r.get("speedup_over_one_thread") is not None for r in rows.rows):
        out.append("\n### {} threads over one, each render timed again on one thread right after it "
                   "(--scaling): median of the pairs, scalar\n".format(tn))
        body = []
        for scene in rows.scenes:
            cells = [scene]
            for s in STRUCTURES + ("embree",):
                traversal = "rtcIntersect1" if s == "embree" else "scalar"
                cells.append(fmt(rows.value("speedup_over_one_thread", scene, s, traversal, tn)))
            body.append(cells)
        out.append(table(["scene"] + [NAMES[s] for s in STRUCTURES] + ["Embree rtcIntersect1"], body))

    if any(r["structure"] == "embree" for r in rows.rows):
        out.append("\n### Ours over Embree on the same rays: BVH scalar / rtcIntersect1, BVH simdN / rtcIntersectN\n")
        body = []
        for scene in rows.scenes:
            for t in rows.threads:
                cells = [scene, t]
                for w in widths:
                    cells.append(fmt(ratio(rows.value("mrays_per_s", scene, "bvh", w, t),
                                           rows.value("mrays_per_s", scene, "embree", EMBREE_CALL[w], t))))
                best = max((rows.value("mrays_per_s", scene, s, widths[-1], t) or 0) for s in STRUCTURES)
                cells.append(fmt(ratio(best, rows.value("mrays_per_s", scene, "embree", EMBREE_CALL[widths[-1]], t))))
                body.append(cells)
        out.append(table(["scene", "threads"] + widths + ["best structure at {}".format(widths[-1])], body))

    out.append("\n### Nodes / triangles per ray, {} threads (packet rows: a packet's visit shared among its rays)\n"
               .format(tn))
    body = []
    shown = [w for w in ("scalar", widths[-1])]
    for scene in rows.scenes:
        cells = [scene]
        for s in STRUCTURES:
            for w in shown:
                r = rows.get(scene, s, w, tn)
                cells.append("-" if r is None or r["nodes_per_ray"] is None else
                             "{} / {}".format(fmt(r["nodes_per_ray"]), fmt(r["triangles_per_ray"])))
        body.append(cells)
    out.append(table(["scene"] + ["{} {}".format(NAMES[s], w) for s in STRUCTURES for w in shown], body))

    out.append("\n### Error against {}, {} threads, scalar (hit/miss % / triangle % / largest relative t "
               "difference)\n".format(report.get("reference", "the reference"), tn))
    body = []
    for scene in rows.scenes:
        cells = [scene]
        for s in STRUCTURES:
            r = rows.get(scene, s, "scalar", tn)
            cells.append("-" if r is None or r["hit_miss_share"] is None else "{} / {} / {}".format(
                fmt(100 * r["hit_miss_share"]), fmt(100 * r["triangle_share"]), fmt(r["max_relative_t_difference"], 2)))
        body.append(cells)
    out.append(table(["scene"] + [NAMES[s] for s in STRUCTURES], body))
    return "\n".join(out)


def variants(report):
    rows = Rows(report)
    t = rows.threads[-1]
    kinds = []
    for r in rows.rows:
        k = (r["triangle_test"], r["slabs"])
        if r["structure"] != "embree" and k not in kinds:
            kinds.append(k)
    widths = [w for w in WIDTHS if any(r["traversal"] == w for r in rows.rows)]
    label = {("watertight", "robust"): "WT robust", ("watertight", "fast"): "WT fast",
             ("moller_trumbore", "robust"): "MT robust", ("moller_trumbore", "fast"): "MT fast"}
    out = ["### Mrays/s by variant, {} threads, {}x{} ({})\n".format(t, report["width"], report["height"],
                                                                    ", ".join(label.get(k, str(k)) for k in kinds))]
    body = []
    for scene in rows.scenes:
        for s in STRUCTURES:
            for w in widths:
                cells = [scene, NAMES[s], w]
                base = rows.value("mrays_per_s", scene, s, w, t, triangle_test=kinds[0][0], slabs=kinds[0][1])
                for k in kinds:
                    v = rows.value("mrays_per_s", scene, s, w, t, triangle_test=k[0], slabs=k[1])
                    cells.append(fmt(v) if k == kinds[0] else "{} ({}x)".format(fmt(v), fmt(ratio(v, base))))
                body.append(cells)
    out.append(table(["scene", "structure", "traversal"] + [label.get(k, str(k)) for k in kinds], body))

    out.append("\n### Error by variant against {} (hit/miss % / triangle %), scalar rows; packet rows equal "
               "them\n".format(report.get("reference", "the reference")))
    body = []
    for scene in rows.scenes:
        for s in STRUCTURES:
            cells = [scene, NAMES[s]]
            for k in kinds:
                r = rows.get(scene, s, "scalar", t, triangle_test=k[0], slabs=k[1])
                cells.append("-" if r is None or r["hit_miss_share"] is None else "{} / {}".format(
                    fmt(100 * r["hit_miss_share"]), fmt(100 * r["triangle_share"])))
            body.append(cells)
    out.append(table(["scene", "structure"] + [label.get(k, str(k)) for k in kinds], body))

    out.append("\n### Median over the scenes of each variant's speed over watertight/robust\n")
    body = []
    for s in STRUCTURES:
        for w in widths:
            cells = [NAMES[s], w]
            for k in kinds[1:]:
                ratios = [ratio(rows.value("mrays_per_s", sc, s, w, t, triangle_test=k[0], slabs=k[1]),
                                rows.value("mrays_per_s", sc, s, w, t, triangle_test=kinds[0][0], slabs=kinds[0][1]))
                          for sc in rows.scenes]
                ratios = [x for x in ratios if x is not None]
                cells.append(fmt(statistics.median(ratios)) if ratios else "-")
            body.append(cells)
    out.append(table(["structure", "traversal"] + [label.get(k, str(k)) for k in kinds[1:]], body))
    return "\n".join(out)


def ray_kinds(report):
    rows = report["rows"]
    t = max(report["threads"])
    kinds = [k for k in ("primary", "shadow", "diffuse") if any(r.get("rays") == k for r in rows)]

    def mrays(scene, structure, traversal, kind):
        for r in rows:
            if (r["scene"], r["structure"], r["traversal"], r["threads"], r.get("rays")) == \
                    (scene, structure, traversal, t, kind):
                return r["mrays_per_s"]
        return None

    traversals = [w for w in WIDTHS if any(r["traversal"] == w for r in rows)]
    out = ["### Mrays/s by ray kind, {} threads, {}x{} ({})\n".format(
        t, report["width"], report["height"], " / ".join(kinds))]
    body = []
    for scene in scenes_in_order(rows):
        for s in STRUCTURES + ("embree",):
            for w in traversals:
                traversal = w
                if s == "embree":
                    # Embree's rows name their calls: rtcIntersectN for primary and diffuse, rtcOccludedN
                    # for shadow; match them by width.
                    lanes = "1" if w == "scalar" else w[4:]
                    found = {k: next((r["mrays_per_s"] for r in rows if r["scene"] == scene and
                                      r["structure"] == "embree" and r["threads"] == t and r.get("rays") == k and
                                      re.search(r"(\d+)$", r["traversal"]).group(1) == lanes), None)
                             for k in kinds}
                    traversal = "width " + lanes
                else:
                    found = {k: mrays(scene, s, w, k) for k in kinds}
                if all(v is None for v in found.values()):
                    continue
                cells = [scene, NAMES[s], traversal] + [fmt(found[k]) for k in kinds]
                cells.append(fmt(ratio(found.get("shadow"), found.get("primary"))))
                body.append(cells)
    out.append(table(["scene", "structure", "traversal"] + kinds + ["shadow / primary"], body))
    return "\n".join(out)


PAIRED = (("bvh", "paired_over_scalar", "BVH x scalar"), ("bvh", "paired_over_embree", "BVH x Embree"),
          ("kdtree", "paired_over_scalar", "KD x scalar"), ("kdtree", "paired_over_bvh", "KD x BVH"),
          ("kdtree", "paired_over_embree", "KD x Embree"), ("octree", "paired_over_scalar", "Octree x scalar"),
          ("octree", "paired_over_bvh", "Octree x BVH"), ("octree", "paired_over_embree", "Octree x Embree"))


def paired(report):
    """The --paired ratios, one row per scene and traversal, each cell 'first thread count / next ...'."""
    rows = Rows(report)
    columns = [c for c in PAIRED if any(r["structure"] == c[0] and r.get(c[1]) is not None for r in rows.rows)]
    traversals = [w for w in WIDTHS if any(r["traversal"] == w for r in rows.rows)]

    def two_decimals(x):
        return "-" if x is None else "{:.2f}".format(x)

    body = []
    for scene in rows.scenes:
        for w in traversals:
            cells = []
            for structure, key, _ in columns:
                values = [rows.value(key, scene, structure, w, t, triangle_test="watertight", slabs="robust")
                          for t in rows.threads]
                cells.append("-" if all(v is None for v in values) else " / ".join(two_decimals(v) for v in values))
            body.append([scene, w] + cells)
    return table(["scene", "traversal"] + [c[2] for c in columns], body)


def sweep(reports):
    out = []
    for report in reports:
        rows = [r for r in Rows(report).rows if r["sweep_value"] is not None]
        t = max(report["threads"])
        rows = [r for r in rows if r["threads"] == t and r["traversal"] == "scalar"]
        values = sorted({r["sweep_value"] for r in rows})
        name = report["sweep"]["name"]
        out.append("### Sweep {} ({}), {}x{}, {} threads, scalar: render ms (build ms)\n".format(
            name, report["sweep"]["parameter"], report["width"], report["height"], t))
        body = []
        for scene in scenes_in_order(rows):
            mine = {r["sweep_value"]: r for r in rows if r["scene"] == scene}
            best = min(mine.values(), key=lambda r: r["render_ms"])["sweep_value"]
            cells = [scene]
            for v in values:
                r = mine.get(v)
                if r is None:
                    cells.append("-")
                    continue
                text = "{} ({})".format(fmt(r["render_ms"]), fmt(r["build_ms"]))
                cells.append("**{}**".format(text) if v == best else text)
            body.append(cells)
        out.append(table(["scene"] + ["{:g}".format(v) for v in values], body))
        out.append("")
    return "\n".join(out)


def stress(reports):
    out = ["### Stress suite: rays, leaks and disagreements per structure and width (closest + any hit)\n"]
    body = []
    for report in reports:
        variant = "{} / {}".format(report.get("triangle_test", "watertight"), report.get("slabs", "robust"))
        configs = []
        for r in report["rows"]:
            if (r["accel"], r["simd"]) not in configs:
                configs.append((r["accel"], r["simd"]))
        for accel, simd in configs:
            mine = [r for r in report["rows"] if (r["accel"], r["simd"]) == (accel, simd)]
            body.append([variant, accel, simd, report["rays_per_case"], sum(r["rays"] for r in mine),
                         sum(r["leaks"] for r in mine),
                         sum(r["hit_miss_disagreements"] + r["triangle_disagreements"] + r["t_beyond_tolerance"]
                             + r["non_finite"] for r in mine),
                         sum(1 for r in mine if r["leaks"] or r["hit_miss_disagreements"] or
                             r["triangle_disagreements"] or r["t_beyond_tolerance"] or r["non_finite"]),
                         fmt(statistics.median(r["mrays_per_s"] for r in mine))])
    out.append(table(["triangle test / slabs", "structure", "width", "rays per case", "rays traced", "leaks",
                      "other failures", "failing case rows", "median Mrays/s over cases"], body))
    return "\n".join(out)


def load(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError) as e:
        sys.exit("summarize.py: {}: {}".format(path, e))


BENCH_DIR = os.path.dirname(os.path.abspath(__file__))
SHARED_DIR = os.path.join(BENCH_DIR, "..", "..", "shared")


def page_main(argv):
    """summarize.py page | check: RESULTS.md from the run set's manifest, or checked against it."""
    import results_page

    parser = argparse.ArgumentParser(prog="summarize.py " + argv[0])
    if argv[0] == "check":
        parser.add_argument("results_md", help="the page to check, e.g. bench/RESULTS.md")
    parser.add_argument("--run", default=os.path.join(BENCH_DIR, "results", "run.json"),
                        help="the run set's manifest, written by bench/reproduce.sh")
    parser.add_argument("--study-table", default=os.path.join(SHARED_DIR, "BENCHMARK.md"))
    parser.add_argument("--scenes", default=os.path.join(SHARED_DIR, "scenes", "scenes.json"),
                        help="the scenes' manifest, for their kinds (simple, complex)")
    parser.add_argument("--targets", default=os.path.join(BENCH_DIR, "targets.json"))
    if argv[0] == "page":
        parser.add_argument("--out", help="write the page here instead of printing it")
    args = parser.parse_args(argv[1:])
    try:
        text = results_page.page(args.run, args.study_table, args.scenes, args.targets)
    except results_page.PageError as e:
        sys.exit("summarize.py: {}".format(e))
    if argv[0] == "page":
        if args.out:
            with open(args.out, "w") as f:
                f.write(text)
        else:
            sys.stdout.write(text)
        return 0
    try:
        with open(args.results_md) as f:
            current = f.read()
    except OSError as e:
        sys.exit("summarize.py: {}: {}".format(args.results_md, e.strerror))
    if current == text:
        print("{}: generated from {}, unchanged".format(args.results_md, args.run))
        return 0
    diff = list(difflib.unified_diff(current.splitlines(), text.splitlines(), args.results_md, "generated",
                                     lineterm=""))
    sys.stderr.write("\n".join(diff[:60]) + ("\n..." if len(diff) > 60 else "") + "\n")
    sys.stderr.write("summarize.py: {} differs from the page {} gives ({} lines of difference); "
                     "run: /usr/bin/python3 bench/summarize.py page --out {}\n".format(
                         args.results_md, args.run, len(diff), args.results_md))
    return 1


def main():
    if len(sys.argv) > 1 and sys.argv[1] in ("page", "check"):
        sys.exit(page_main(sys.argv[1:]))
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("kind", choices=("study", "variants", "sweep", "stress", "ray-kinds", "paired"))
    parser.add_argument("json", nargs="+")
    parser.add_argument("--study-table", default="../shared/BENCHMARK.md",
                        help="BENCHMARK.md, for the study's own Table 2 (skipped when absent)")
    args = parser.parse_args()
    reports = [load(p) for p in args.json]
    if args.kind == "study":
        print(study(reports[0], args.study_table))
    elif args.kind == "variants":
        print(variants(reports[0]))
    elif args.kind == "sweep":
        print(sweep(reports))
    elif args.kind == "ray-kinds":
        print(ray_kinds(reports[0]))
    elif args.kind == "paired":
        print(paired(reports[0]))
    else:
        print(stress(reports))


if __name__ == "__main__":
    main()
