"""bench/RESULTS.md, generated whole from one run set of bench/reproduce.sh.

The run set is a manifest (bench/results/run.json, written by reproduce.sh: the commit, the date,
each step's command and seconds, the JSON files and the charts) and the trident-bench JSON it
names. Every figure on the page is read or computed from those files; the study's own Table 2 and
the scenes' kinds are read from ../shared (BENCHMARK.md and scenes/scenes.json). The prose is fixed
and holds no figure. The targets come from bench/targets.json: what each issue asks, how to measure
it on the run's rows, and why a target is missed, in words, with a link to the trials.

Structures are found in the rows, not listed here: a structure of ours added later (a wide BVH,
named `bvh8` or given a `bvh_width` column) gets its own columns, and Embree rows of any call
(rtcIntersectN, rtcOccludedN, streams) their own cells. Only the standard library is used.
"""
import json
import os
import statistics

from summarize import LABELS, fmt, ordered, ratio, read_study_table, scenes_in_order, table

KINDS = ("primary", "shadow", "diffuse")
STUDY_STRUCTURES = (("bvh", "BVH"), ("kdtree", "KD"), ("octree", "Octree"))
TRAVERSAL_ORDER = ("scalar", "simd4", "simd8", "simd16")


class PageError(Exception):
    """A run set the page cannot be made from (missing file, two machines, no rows)."""


def structure_of(row):
    """The structure's label: its name, with its node width when the row has one above two."""
    width = row.get("bvh_width") or row.get("node_width")
    if width and width != 2 and not row["structure"].endswith(str(width)):
        return "{}{}".format(row["structure"], width)
    return row["structure"]


def study_structure(structure):
    """The study's structure one of ours stands for: the wide BVH and the binary BVH-2 are both its BVH."""
    return "bvh" if structure.rstrip("0123456789") == "bvh" else structure


def is_embree(row):
    """Embree's rows, whatever their call (`embree`, or a name of its own for a stream row)."""
    return row["structure"].startswith("embree")


def name_of(structure):
    if structure in LABELS:
        return LABELS[structure]
    base = structure.rstrip("0123456789")
    return "{}-{}".format(LABELS.get(base, base), structure[len(base):]) if base != structure else structure


def plural(count, noun):
    return "{} {}{}".format(count, noun, "" if count == 1 else "s")


def per_thread_count(run):
    """What a cell of values per thread count holds, e.g. '1 thread / 2 threads'."""
    return " / ".join(plural(t, "thread") for t in run.threads)


def two(x):
    return "-" if x is None else "{:.2f}".format(x)


def span(values, digits=two):
    values = [v for v in values if v is not None]
    if not values:
        return "-"
    lo, hi = min(values), max(values)
    return digits(lo) if digits(lo) == digits(hi) else "{}–{}".format(digits(lo), digits(hi))


class Run:
    """The rows of one trident-bench JSON, by the keys the page looks them up by."""

    def __init__(self, name, path, report):
        self.name, self.path, self.report = name, path, report
        # The default variant only (watertight triangles, robust slabs): the page's figures are the
        # product's; the variants' are trials.
        self.rows = [r for r in report["rows"] if r.get("sweep_value") is None and
                     r.get("triangle_test") in (None, "watertight") and r.get("slabs") in (None, "robust")]
        self.scenes = scenes_in_order(self.rows)
        self.threads = sorted(set(report["threads"]))
        self.kinds = [k for k in KINDS if any(r.get("rays", "primary") == k for r in self.rows)]

    def ours(self, **match):
        return [r for r in self.select(**match) if not is_embree(r)]

    def embree(self, **match):
        return [r for r in self.select(**match) if is_embree(r)]

    def select(self, **match):
        out = []
        for r in self.rows:
            if all((structure_of(r) if k == "structure" else r.get(k, "primary" if k == "rays" else None)) == v
                   for k, v in match.items()):
                out.append(r)
        return out

    def one(self, **match):
        found = self.select(**match)
        return found[0] if found else None

    def structures(self, **match):
        return ordered([structure_of(r) for r in self.ours(**match)], [s for s, _ in STUDY_STRUCTURES])

    def traversals(self, **match):
        return ordered([r["traversal"] for r in self.ours(**match)], TRAVERSAL_ORDER)

    def partner(self, row, **override):
        """The row traced on the same rays as `row` (scene, threads, ray kind, variant) with `override`."""
        match = {"scene": row["scene"], "threads": row["threads"], "rays": row.get("rays", "primary"),
                 "structure": structure_of(row), "traversal": row["traversal"]}
        match.update(override)
        if override.get("structure") != "embree":
            match.update(triangle_test=row.get("triangle_test"), slabs=row.get("slabs"))
        return self.one(**match)


def load_json(path):
    try:
        with open(path) as f:
            return json.load(f)
    except OSError as e:
        raise PageError("{}: {}".format(path, e.strerror))
    except ValueError as e:
        raise PageError("{}: not JSON: {}".format(path, e))


class RunSet:
    """The manifest and its runs; refuses runs of more than one machine."""

    def __init__(self, manifest_path):
        self.path = manifest_path
        self.dir = os.path.dirname(manifest_path)
        self.manifest = load_json(manifest_path)
        for key in ("commit", "date", "runs"):
            if key not in self.manifest:
                raise PageError("{}: no '{}'".format(manifest_path, key))
        self.runs = {}
        for step in self.manifest["runs"]:
            path = os.path.join(self.dir, step["json"])
            try:
                self.runs[step["name"]] = Run(step["name"], step["json"], load_json(path))
            except (KeyError, TypeError) as e:
                raise PageError("{}: not trident-bench JSON (no {})".format(path, e))
        machines = {json.dumps(r.report["machine"], sort_keys=True) for r in self.runs.values()}
        if len(machines) > 1:
            raise PageError("{}: its runs were made on {} machines: {}".format(
                manifest_path, len(machines), "; ".join(sorted(machines))))
        if "primary" not in self.runs:
            raise PageError("{}: no run named 'primary'".format(manifest_path))
        self.machine = next(iter(self.runs.values())).report["machine"]
        # The portable build against the native one (bench/compare_builds.py) and the clean-clone
        # times of run.sh (bench/time_setup.sh): optional, and of the same machine when present.
        self.portable = self.extra("portable", lambda data: data["machine"]["cpu"])
        # The native build against itself by the same method: the method's own noise on this machine.
        self.portable_self = self.extra("portable_self", lambda data: data["machine"]["cpu"])
        self.setup = self.extra("setup", lambda data: data["cpu"])
        # The Python module against the C++ renderer (bench/python_bench.py).
        self.python = self.extra("python", lambda data: data["machine"]["cpu"])
        # Hit buffers under every ISA cap (bench/compare_caps.py).
        self.caps = self.extra("caps", lambda data: data["machine"]["cpu"])

    def extra(self, key, cpu_of):
        if key not in self.manifest:
            return None
        path = os.path.join(self.dir, self.manifest[key])
        data = load_json(path)
        try:
            cpu = cpu_of(data)
        except (KeyError, TypeError):
            raise PageError("{}: names no CPU".format(path))
        if cpu != self.machine.get("cpu"):
            raise PageError("{}: measured on {}, the run set on {}".format(path, cpu, self.machine.get("cpu")))
        return data

    def run_for(self, kind):
        """The run whose rows of `kind` the page shows: 'primary' for primary rays, else the first
        run that has the kind."""
        if kind == "primary":
            return self.runs["primary"]
        return next((r for r in self.runs.values() if kind in r.kinds), None)


def read_scene_kinds(path):
    """{scene: 'simple' | 'complex'} from a BENCHMARK.md manifest; {} when absent."""
    try:
        with open(path) as f:
            data = json.load(f)
    except (OSError, ValueError):
        return {}
    entries = data if isinstance(data, list) else data.get("scenes", [])
    return {e["name"]: e.get("kind") for e in entries if "name" in e}


# ---- Sections ------------------------------------------------------------------------------------

def run_label(run):
    return "`results/{}` ({}x{}, run `{}`)".format(run.path, run.report["width"], run.report["height"], run.name)


def machine_section(runs):
    m, man = runs.machine, runs.manifest
    out = ["## The machine, the code, the command", ""]
    commit = "`{}`{}".format(man["commit"], " with uncommitted changes" if man.get("dirty") else "")
    out.append("- Machine: {}, {} cores, {} hardware threads; {}; Embree {}.".format(
        m.get("cpu", "?"), m.get("physical_cores", "?"), m.get("hardware_threads", "?"), m.get("compiler", "?"),
        m.get("embree_version", "none")))
    out.append("- Code: commit {}, measured {} (the run set's start; every table below is of this run set).".format(
        commit, man["date"]))
    primary = runs.runs["primary"].report
    out.append("- Times: medians of {} after {}; reference for the error columns: {}.".format(
        plural(primary["repeats"], "run"), plural(primary["warmup_runs"], "warm-up"), primary.get("reference", "-")))
    out.append("- Regenerate it all on this machine: `bash bench/reproduce.sh` (it builds `build-native/` and "
               "`build-portable/`, runs the "
               "steps below, draws the charts and writes this page with `/usr/bin/python3 bench/summarize.py page`); "
               "`bench/summarize.py check bench/RESULTS.md` says whether the page and the JSON still agree.")
    out.append("")
    body = []
    for step in man.get("steps", []):
        body.append([step["name"], "`{}`".format(step["command"]), "{:.1f}".format(step["seconds"] / 60)])
    out.append(table(["step", "command", "minutes"], body))
    total = sum(step["seconds"] for step in man.get("steps", []))
    out.append("")
    out.append("The run set took {:.1f} minutes.".format(total / 60))
    return out


def study_section(runs, study):
    run = runs.runs["primary"]
    t = run.threads[-1]
    ours = run.structures(rays="primary")
    traversals = run.traversals(rays="primary")
    packet = traversals[-1] if len(traversals) > 1 else None
    out = ["## The study's Table 2 beside ours", ""]
    if not study:
        out.append("(../shared/BENCHMARK.md is absent: the study's table cannot be quoted.)")
        return out
    out.append("The study: AMD Ryzen 5 2600, 12 threads. Ours: {} thread{}, from {}. Each cell: the study / ours "
               "single rays{}; build and render in s.".format(
                   t, "" if t == 1 else "s", run_label(run),
                   " / ours {} packets".format(packet) if packet else ""))
    out.append("")
    shown = [s for s, _ in STUDY_STRUCTURES if s in ours]
    extra = [s for s in ours if s not in shown]
    header = ["scene", "triangles"]
    for what in ("build", "render", "Mrays/s"):
        header += ["{} {}".format(what, label) for s, label in STUDY_STRUCTURES if s in shown]
        header += ["{} {} (ours)".format(what, name_of(s)) for s in extra]
    body = []
    for scene in run.scenes:
        ref = study.get(scene, {})
        cells = [scene, ref.get("triangles") or str(run.ours(scene=scene)[0]["triangles"])]
        for what, field, scale in (("build", "build_ms", 1e-3), ("render", "render_ms", 1e-3),
                                   ("Mrays/s", "mrays_per_s", 1.0)):
            for s in shown + extra:
                label = dict(STUDY_STRUCTURES).get(s)
                widths = ["scalar"] if what == "build" else ["scalar"] + ([packet] if packet else [])
                mine = []
                for w in widths:
                    r = run.one(scene=scene, structure=s, traversal=w, threads=t, rays="primary")
                    mine.append(fmt(None if r is None or r[field] is None else r[field] * scale))
                study_cell = [ref.get("{} {}".format(what, label), "-")] if label else []
                cells.append(" / ".join(study_cell + mine))
        body.append(cells)
    out.append(table(header, body))
    return out


def embree_section(runs):
    out = ["## Ours against Embree on the same rays", "",
           "Embree's time over ours on the same rays, so above 1 is faster than Embree: single rays against "
           "rtcIntersect1 (rtcOccluded1 for shadow rays), packets against rtcIntersectN / rtcOccludedN of the "
           "same width (diffuse packets: rtcIntersect1). A cell holds one figure per thread count. A plain figure "
           "is paired (`--paired embree`: each render followed by Embree's on the same rays, the median of the "
           "pairs' ratios); a figure marked * is the ratio of the two rows' medians, taken minutes apart, for "
           "rows the run did not pair. The wide BVH's shadow rows test the block of triangles that stopped the "
           "ray (or packet) before each ray first, as the renderer traces them (`--last-occluder`, "
           "bench/README.md), which Embree's rtcOccluded calls do not; the other structures' rows only walk."]
    for kind in KINDS:
        run = runs.run_for(kind)
        if run is None or not any(r.get("paired_over_embree") is not None or r.get("ratio_to_embree") is not None
                                  for r in run.ours(rays=kind)):
            continue
        out += ["", "### {} rays, from {}: {}".format(kind.capitalize(), run_label(run), per_thread_count(run)), ""]

        def cell(scene, s, w):
            values = []
            for t in run.threads:
                r = run.one(scene=scene, structure=s, traversal=w, threads=t, rays=kind)
                if r is not None and r.get("paired_over_embree") is not None:
                    values.append(two(r["paired_over_embree"]))
                elif r is not None and r.get("ratio_to_embree") is not None:
                    values.append(two(r["ratio_to_embree"]) + "*")
                else:
                    values.append("-")
            return " / ".join(values)

        columns = [(s, w) for s in run.structures(rays=kind) for w in run.traversals(rays=kind)
                   if any(cell(scene, s, w).strip("- /") for scene in run.scenes)]
        body = [[scene] + [cell(scene, s, w) for s, w in columns] for scene in run.scenes]
        out.append(table(["scene"] + ["{} {}".format(name_of(s), w) for s, w in columns], body))
    return out


def build_section(runs):
    run = runs.runs["primary"]
    structures = run.structures(rays="primary") + (["embree"] if run.embree(rays="primary") else [])
    out = ["## Build time, memory and error", "",
           "From {}. Build: ms from the triangles in memory to the structure ready to trace, {}. Memory: bytes the structure holds per triangle (Embree: what its memory monitor saw the "
           "scene allocate). Error: against {}, single rays at {} threads: rays whose hit or miss differs % / "
           "rays whose hit triangle differs % / the largest relative difference in hit distance.".format(
               run_label(run), per_thread_count(run), run.report.get("reference", "the reference"), run.threads[-1]),
           ""]

    def scalar_row(scene, s, t):
        """The structure's single-ray row (its build, memory and errors), else its first row."""
        if s == "embree":
            return next((r for r in run.embree(scene=scene, threads=t, rays="primary")
                         if r["traversal"].endswith("1")), None)
        return run.one(scene=scene, structure=s, traversal="scalar", threads=t, rays="primary") or \
            run.one(scene=scene, structure=s, threads=t, rays="primary")

    # The wide BVH's builder per scene, where the run names it (the default, auto, picks it per mesh).
    with_builder = "bvh" in structures and any(r.get("builder") for r in run.ours(structure="bvh"))
    if with_builder:
        out[-1:-1] = ["", "The wide BVH's builder column names the tree each scene got from the build it ran with "
                      "(`auto`, the default: the tree with spatial splits where the mesh has large triangles and that "
                      "tree's SAH is lower, else the binned one; its build time counts every tree it built)."]
    body = []
    for scene in run.scenes:
        cells = [scene, str(run.select(scene=scene)[0]["triangles"])]
        if with_builder:
            r = scalar_row(scene, "bvh", run.threads[-1])
            cells.append("-" if r is None or not r.get("builder") else r["builder"])
        for s in structures:
            cells.append(" / ".join(fmt(None if r is None else r["build_ms"])
                                    for r in (scalar_row(scene, s, t) for t in run.threads)))
        for s in structures:
            r = scalar_row(scene, s, run.threads[-1])
            cells.append(fmt(None if r is None else r["bytes_per_triangle"]))
        body.append(cells)
    out.append(table(["scene", "triangles"] + (["builder {}".format(name_of("bvh"))] if with_builder else []) +
                     ["build ms {}".format(name_of(s)) for s in structures] +
                     ["bytes/tri {}".format(name_of(s)) for s in structures], body))
    out.append("")
    body = []
    ours = run.structures(rays="primary")
    for scene in run.scenes:
        cells = [scene]
        for s in ours:
            r = scalar_row(scene, s, run.threads[-1])
            cells.append("-" if r is None or r["hit_miss_share"] is None else "{} / {} / {}".format(
                fmt(100 * r["hit_miss_share"]), fmt(100 * r["triangle_share"]), fmt(r["max_relative_t_difference"], 2)))
        body.append(cells)
    out.append(table(["scene"] + ["error {}".format(name_of(s)) for s in ours], body))
    return out


def step_command(runs, name):
    return next((s["command"] for s in runs.manifest.get("steps", []) if s["name"] == name), None)


def structure_by_traversal(rows, column):
    """A table of a structure a line and a traversal a column; a cell: `column` over the rows of that
    structure and traversal, lowest–highest, then their median."""
    structures = ordered([r["structure"] for r in rows], ["bvh", "bvh2", "kdtree", "octree"])
    traversals = ordered([r["traversal"] for r in rows], TRAVERSAL_ORDER)
    body = []
    for s in structures:
        cells = [name_of(s)]
        for t in traversals:
            values = [r[column] for r in rows if r["structure"] == s and r["traversal"] == t]
            cells.append("-" if not values else "{} ({})".format(span(values), two(statistics.median(values))))
        body.append(cells)
    return table(["structure"] + list(traversals), body)


def portable_section(runs):
    data = runs.portable
    out = ["## The portable build against the native one", ""]
    if data is None:
        return out + ["Not measured by this run set (its `portable` step did not run)."]
    out += ["What `run.sh test` builds and users get (`TRIDENT_MARCH=portable`: an x86-64-v2 baseline, kernels "
            "for SSE4.2, AVX2 and AVX-512 chosen at run time) against the native build measured above, on the "
            "same rays: {}, each a pair of runs per scene and structure seconds apart, the order "
            "alternating; one thread. A cell: the rows' medians of the portable build's speed over the native's, "
            "lowest–highest over the scenes (`{}`) and ray kinds, then their median. Command: `{}`.".format(
                plural(data["rounds"], "round"), data["each_scene"], step_command(runs, "portable") or "-"), ""]
    rows = data["rows"]
    out.append(structure_by_traversal(rows, "median"))
    every = [r["median"] for r in rows]
    out += ["", "{} rows; their medians {}, the median of those {}.".format(len(every), span(every),
                                                                           two(statistics.median(every)))]
    control = runs.portable_self
    if control is not None:
        # A ratio of 1 by construction: how far a row's median strays from it is the method's noise,
        # and a portable row below the control's lowest is a loss the method can see.
        medians = [r["median"] for r in control["rows"]]
        scenes = {r["scene"] for r in control["rows"]}
        compared = [r["median"] for r in rows if r["scene"] in scenes]
        out += ["", "The method's noise: the native build against itself, the same way ({}, scenes `{}`): {} rows, "
                "their medians {}; the portable build's rows on those scenes below its lowest: {} of {}. "
                "Command: `{}`.".format(
                    plural(control["rounds"], "round"), control["each_scene"], len(medians), span(medians),
                    sum(m < min(medians) for m in compared), len(compared),
                    step_command(runs, "portable_self") or "-")]
    return out


def isa_cap_section(runs):
    """The run made under TRIDENT_ISA's cap (run `avx2`): ours against Embree limited the same way."""
    run = runs.runs.get("avx2")
    out = ["## AVX2 as our users have it", ""]
    if run is None:
        return out + ["Not measured by this run set (its `avx2` step did not run)."]
    out += ["The portable build under `TRIDENT_ISA={}` (the kernels a CPU without AVX-512 runs, such as the study's "
            "Ryzen) against Embree limited the same way (`max_isa={}`), on the same rays, {} ({}x{}): Embree's "
            "time over ours, paired as above (single rays against rtcIntersect1 or rtcOccluded1, packets against "
            "Embree's call of the same width). Command: `{}`.".format(
                run.report.get("isa_cap") or "-", run.report.get("embree_isa") or "-", per_thread_count(run),
                run.report["width"], run.report["height"], step_command(runs, "avx2") or "-"), ""]
    kinds = [k for k in KINDS if run.ours(rays=k)]
    columns = [(s, w, k) for s in run.structures() for w in run.traversals() for k in kinds
               if run.ours(structure=s, traversal=w, rays=k)]

    def cell(scene, s, w, k):
        values = [r.get("paired_over_embree") for t in run.threads
                  for r in [run.one(scene=scene, structure=s, traversal=w, threads=t, rays=k)] if r is not None]
        return " / ".join("-" if v is None else two(v) for v in values) or "-"

    out.append(table(["scene"] + ["{} {}, {}".format(name_of(s), w, k) for s, w, k in columns],
                     [[scene] + [cell(scene, s, w, k) for s, w, k in columns] for scene in run.scenes]))
    return out


def caps_section(runs):
    data = runs.caps
    out = ["## The same hits under every instruction set", ""]
    if data is None:
        return out + ["Not measured by this run set (its `caps` step did not run)."]
    rows = data["rows"]
    caps = ordered([r["cap"] for r in rows], ["sse4", "avx2", "avx512"])
    out += ["The portable build's primary-ray hit buffers (BENCHMARK.md's format, {}x{}) under each `TRIDENT_ISA` "
            "cap, every structure and every packet width the cap allows, compared byte for byte with the same "
            "binary's single rays without a cap (`bench/compare_caps.py`). A cell: the buffers that differ, of "
            "those compared, and the rays they differ in. Command: `{}`.".format(
                data["width"], data["height"], step_command(runs, "caps") or "-"), ""]
    structures = ordered([r["structure"] for r in rows], ["bvh", "bvh2", "kdtree", "octree"])
    body = []
    for s in structures:
        cells = [name_of(s)]
        for cap in caps:
            mine = [r for r in rows if r["structure"] == s and r["cap"] == cap]
            cells.append("{} of {} ({} rays)".format(sum(r["differing_rays"] > 0 for r in mine), len(mine),
                                                     sum(r["differing_rays"] for r in mine)))
        body.append(cells)
    out.append(table(["structure"] + ["differ under {}".format(c) for c in caps], body))
    for skipped in data.get("skipped", []):
        out += ["", "Not run under `{}` on this CPU: {}".format(skipped["cap"], skipped["why"])]
    return out


def python_section(runs):
    data = runs.python
    out = ["## The Python module against the C++ renderer", ""]
    if data is None:
        return out + ["Not measured by this run set (its `python` step did not run)."]
    rows = data["rows"]
    if not rows:
        return out + ["Its `python` step measured no rows."]
    differing = sum(r["differing_hits"] for r in rows)
    out += ["`scene.intersect(rays)` of the Python module on `trident.camera_rays(...)` of BENCHMARK.md's camera "
            "against trident-bench's render of the same rays, same structure and traversal, {} ({}x{}): in each of "
            "{}, trident-bench's median of {} renders, then the module's median of as many calls. A cell: the "
            "medians over rounds of the module's time over the C++ one, lowest–highest over the scenes, then their "
            "median. Rays whose hit (triangle or t) differs from trident-bench's hit buffer of the same rays: {}. "
            "Command: `{}`.".format(
                plural(rows[0]["threads"], "thread"), data["width"], data["height"], plural(data["rounds"], "round"),
                data["repeats"], differing, step_command(runs, "python") or "-"), ""]
    out.append(structure_by_traversal(rows, "ratio"))
    return out


def setup_section(runs):
    out = ["## What a newcomer waits", ""]
    if runs.setup is None:
        return out + ["Not measured by this run set (its `setup` step did not run)."]
    out += ["The README's two commands, each from a clean clone of commit `{}` (packages installed, no build "
            "folders, `../shared` beside it), on this machine ({} hardware threads), timed by "
            "`bench/time_setup.sh`.".format(runs.setup["commit"], runs.setup["hardware_threads"]), ""]
    out.append(table(["command", "minutes"], [["`{}`".format(c["command"]), "{:.1f}".format(c["seconds"] / 60)]
                                              for c in runs.setup["commands"]]))
    return out


def fastest(run, scene, kind, threads):
    """Per structure of ours its fastest traversal's row, fastest structure first."""
    best = {}
    for r in run.ours(scene=scene, rays=kind, threads=threads):
        s = structure_of(r)
        if r.get("mrays_per_s") is not None and (s not in best or r["mrays_per_s"] > best[s]["mrays_per_s"]):
            best[s] = r
    return sorted(best.values(), key=lambda r: -r["mrays_per_s"])


def study_winners(study):
    """The study's fastest structure per scene, by its Mrays/s."""
    out = {}
    for scene, ref in study.items():
        speeds = []
        for s, label in STUDY_STRUCTURES:
            try:
                speeds.append((float(ref["Mrays/s " + label]), s))
            except (KeyError, ValueError):
                pass
        if speeds:
            out[scene] = max(speeds)[1]
    return out


def question_section(runs, study, scene_kinds):
    winners = study_winners(study)
    out = ["## The study's question: which structure and traversal is fastest", "",
           "The study concludes that the BVH is fastest on the simple scenes, the KD-tree on the complex ones, "
           "and the Octree last (Table 2, primary rays only). Per ray kind and scene, at the run's largest "
           "thread count: our fastest structure with its fastest traversal, its Mrays/s, and how many times "
           "faster it is than each structure's own fastest traversal (the runner-up first); the study's "
           "fastest for the scene; and Embree's fastest call on the same rays. Ratios of medians of one run. "
           "In the counts under each table either of our BVHs (the wide BVH and the binary BVH-2) stands for "
           "the study's BVH."]
    for kind in KINDS:
        run = runs.run_for(kind)
        if run is None:
            continue
        t = run.threads[-1]
        structures = run.structures(rays=kind, threads=t)
        out += ["", "### {} rays, {} threads, from {}".format(kind.capitalize(), t, run_label(run)), ""]
        body, tally = [], {"agree": 0, "compared": 0, "octree_last": 0, "scenes": 0}
        by_kind = {"simple": [0, 0], "complex": [0, 0]}  # scenes whose fastest is the study's pick, scenes
        for scene in run.scenes:
            ranked = fastest(run, scene, kind, t)
            if not ranked:
                continue
            top = ranked[0]
            cells = [scene, scene_kinds.get(scene, "-")]
            study_best = winners.get(scene)
            cells.append(name_of(study_best) if study_best else "-")
            cells.append("**{} {}**".format(name_of(structure_of(top)), top["traversal"]))
            cells.append(fmt(top["mrays_per_s"]))
            by_structure = {structure_of(r): r for r in ranked}
            for s in structures:
                r = by_structure.get(s)
                if r is None:
                    cells.append("-")
                elif r is top:
                    cells.append("fastest ({})".format(r["traversal"]))
                else:
                    cells.append("{}x ({})".format(two(ratio(top["mrays_per_s"], r["mrays_per_s"])), r["traversal"]))
            calls = run.embree(scene=scene, rays=kind, threads=t)
            best_call = max(calls, key=lambda r: r["mrays_per_s"]) if calls else None
            cells.append("-" if best_call is None else "{} ({}, {}x ours)".format(
                fmt(best_call["mrays_per_s"]), best_call["traversal"],
                two(ratio(best_call["mrays_per_s"], top["mrays_per_s"]))))
            body.append(cells)
            tally["scenes"] += 1
            top_family = study_structure(structure_of(top))
            if study_best and top_family in [s for s, _ in STUDY_STRUCTURES]:
                tally["compared"] += 1
                tally["agree"] += top_family == study_best
            if "octree" in by_structure and ranked[-1] is by_structure["octree"] and len(ranked) > 1:
                tally["octree_last"] += 1
            kind_of_scene = scene_kinds.get(scene)
            if kind_of_scene in by_kind:
                by_kind[kind_of_scene][0] += top_family == ("bvh" if kind_of_scene == "simple" else "kdtree")
                by_kind[kind_of_scene][1] += 1
        out.append(table(["scene", "kind", "study's fastest", "our fastest", "Mrays/s"] +
                         ["over {}".format(name_of(s)) for s in structures] + ["Embree's fastest"], body))
        out.append("")
        summary = ("Our fastest structure is the study's on {} of {} scenes; the Octree is our slowest on {} of {}."
                   .format(tally["agree"], tally["compared"], tally["octree_last"], tally["scenes"]))
        if by_kind["simple"][1]:
            summary += " The BVH is our fastest on {} of the {} simple scenes.".format(*by_kind["simple"])
        if by_kind["complex"][1]:
            summary += " The KD-tree is our fastest on {} of the {} complex scenes.".format(*by_kind["complex"])
        out.append(summary)
    charts = runs.manifest.get("charts", [])
    if charts:
        out += ["", "Charts (bench/plot.py, from the same JSON): " + ", ".join(
            "[{}]({})".format(c["title"], c["path"]) for c in charts) + "."]
    return out


# ---- Targets -------------------------------------------------------------------------------------

def target_rows(runs, spec, scene_kinds):
    if spec["measure"] == "portable_ratio":
        rows = [] if runs.portable is None else runs.portable["rows"]
        return None, [r for r in rows if all(r.get(k) == v for k, v in spec.get("rows", {}).items())]
    if spec["measure"] == "python_ratio":
        return None, [] if runs.python is None else runs.python["rows"]
    if spec["measure"] == "caps_differing":
        return None, [] if runs.caps is None else runs.caps["rows"]
    if spec["measure"] == "setup_seconds":
        commands = [] if runs.setup is None else runs.setup["commands"]
        return None, [dict(c, scene="`{}`".format(c["command"])) for c in commands if c["command"] == spec["command"]]
    run = runs.runs.get(spec.get("run", "primary"))
    if run is None:
        return None, []
    match = dict(spec.get("rows", {}))
    scene_kind = match.pop("scene_kind", None)
    min_triangles = match.pop("min_triangles", None)
    traversals = match.pop("traversals", None)
    rows = [r for r in run.ours(**match)
            if (scene_kind is None or scene_kinds.get(r["scene"]) == scene_kind)
            and (min_triangles is None or r["triangles"] >= min_triangles)
            and (traversals is None or r["traversal"] in traversals)]
    return run, rows


def measure(runs, spec, scene_kinds):
    """[(row, value, paired)] for a target's measure: a column's value, a speed ratio to a partner row
    (the paired column when the run has it), or a column's ratio to a partner's."""
    run, rows = target_rows(runs, spec, scene_kinds)
    out = []
    for r in rows:
        if spec["measure"] == "portable_ratio":
            out.append((r, r["median"], True))
        elif spec["measure"] == "python_ratio":
            out.append((r, r["ratio"], True))
        elif spec["measure"] == "caps_differing":
            out.append((r, r["differing_rays"], False))
        elif spec["measure"] == "setup_seconds":
            out.append((r, r["seconds"], False))
        elif spec["measure"] == "value":
            out.append((r, r.get(spec["column"]), False))
        elif spec["measure"] == "speed_ratio":
            paired = r.get(spec["paired"]) if "paired" in spec else None
            if paired is not None:
                out.append((r, paired, True))
                continue
            if spec["to"].get("structure") == "embree":
                out.append((r, r.get("ratio_to_embree"), False))
                continue
            p = run.partner(r, **spec["to"])
            out.append((r, ratio(r["mrays_per_s"], None if p is None else p["mrays_per_s"]), False))
        elif spec["measure"] == "column_ratio":
            p = run.partner(r, **spec["to"])
            out.append((r, ratio(r.get(spec["column"]), None if p is None else p.get(spec["column"])), False))
        else:
            raise PageError("bench/targets.json: unknown measure '{}'".format(spec["measure"]))
    return [m for m in out if m[1] is not None]


def checked_targets(targets):
    """The targets, each with what the page needs of it, or a PageError naming what it lacks."""
    for i, spec in enumerate(targets):
        missing = [k for k in ("issue", "target", "measure", "reason", "trials") if k not in spec]
        if not ("at_least" in spec) ^ ("at_most" in spec):
            missing.append("one bound, at_least or at_most")
        if spec.get("measure") in ("speed_ratio", "column_ratio") and "to" not in spec:
            missing.append("to")
        if spec.get("measure") in ("value", "column_ratio") and "column" not in spec:
            missing.append("column")
        if spec.get("measure") == "setup_seconds" and "command" not in spec:
            missing.append("command")
        if missing:
            raise PageError("bench/targets.json: target {} ({}) lacks {}".format(
                i + 1, spec.get("target", "unnamed"), ", ".join(missing)))
    return targets


def meets(spec, value):
    return value >= spec["at_least"] if "at_least" in spec else value <= spec["at_most"]


def describe(values, spec):
    figures = [v for _, v, _ in values]
    if spec["measure"] in ("portable_ratio", "python_ratio"):
        return "{} (paired)".format(span(figures))
    if spec["measure"] == "setup_seconds":
        return "{} s".format(span(figures, fmt))
    if spec["measure"] == "caps_differing":
        return "{} of {} hit buffers differ".format(sum(v > 0 for v in figures), len(figures))
    if spec["measure"] != "speed_ratio":
        return (span(figures, fmt if spec["measure"] == "value" else two) + " " + spec.get("unit", "")).strip()
    paired = [p for _, _, p in values]
    return "{} ({})".format(span(figures), "paired" if all(paired) else "unpaired" if not any(paired)
                            else "partly paired")


def targets_section(runs, targets, scene_kinds):
    out = ["## Targets not met", "",
           "Each issue's target measured on this run set (bench/targets.json says how: which rows, which "
           "figure, what bound). A cell is one scene, structure, traversal and thread count; `paired` figures "
           "come from `--paired` pairs, `unpaired` ones from two rows' medians."]
    missed, met, unmeasured = [], [], []
    for spec in targets:
        values = measure(runs, spec, scene_kinds)
        if not values:
            unmeasured.append(spec)
            continue
        failing = [(r, v) for r, v, _ in values if not meets(spec, v)]
        (missed if failing else met).append((spec, values, failing))
    body = []
    for spec, values, failing in missed:
        worst = sorted({r["scene"] for r, _ in failing})
        evidence = []
        for e in spec.get("evidence", []):
            ev = measure(runs, e, scene_kinds)
            if ev:
                evidence.append("{}: {}".format(e["label"], span([v for _, v, _ in ev], two if e["measure"] != "value"
                                                                 else fmt)))
        reason = spec["reason"] + ("" if not evidence else " Measured: " + "; ".join(evidence) + ".")
        body.append(["{}".format(spec["issue"]), spec["target"], describe(values, spec),
                     "{} of {}".format(len(values) - len(failing), len(values)), ", ".join(worst), reason,
                     "[trials]({})".format(spec["trials"])])
    out.append("")
    out.append(table(["issue", "target", "measured", "cells meeting it", "scenes missing it", "why", "trials"], body)
               if body else "Every target measured on this run set is met.")
    if met:
        out += ["", "Met on this run set: " + "; ".join("{} (issue {}: {})".format(
            spec["target"], spec["issue"], describe(values, spec)) for spec, values, _ in met) + "."]
    if unmeasured:
        out += ["", "Not measured by this run set (see the trials): " + "; ".join(
            "{} (issue {}, [trials]({}))".format(s["target"], s["issue"], s["trials"]) for s in unmeasured) + "."]
    return out


def page(manifest_path, study_table_path, scenes_path, targets_path):
    runs = RunSet(manifest_path)
    study = read_study_table(study_table_path)
    scene_kinds = read_scene_kinds(scenes_path)
    targets = checked_targets(load_json(targets_path))
    out = ["# Results", ""]
    if runs.manifest.get("placeholder"):
        out += ["> **Placeholder.** {} Its figures show the page's layout and mean nothing; the lead's full run "
                "of `bench/reproduce.sh` on a quiet machine replaces them.".format(runs.manifest["placeholder"]), ""]
    out += ["The current figures of trident's three structures (and any added since) against the reference "
            "study and Embree, all from one run set of `bench/reproduce.sh` at one commit on one machine, and "
            "generated from its JSON in `bench/results/` by `bench/summarize.py page`: nothing on this page is "
            "typed in. What was tried, kept or dropped, with the figures of older runs and machines, is in "
            "[experiments/](experiments/README.md), one file per topic.", ""]
    for section in (machine_section(runs), study_section(runs, study), embree_section(runs), build_section(runs),
                    question_section(runs, study, scene_kinds), portable_section(runs), isa_cap_section(runs),
                    caps_section(runs), python_section(runs), setup_section(runs),
                    targets_section(runs, targets, scene_kinds)):
        out += section + [""]
    out += ["## Trials", "",
            "[experiments/README.md](experiments/README.md): BVH build, BVH traversal, KD-tree, Octree, packets, "
            "shadow and diffuse rays, numerical robustness, newest first, each trial with its date, commit, "
            "machine, command and figures."]
    return "\n".join(out) + "\n"
