#!/usr/bin/python3
"""bench/RESULTS.md's generator (bench/results_page.py, `summarize.py page` and `check`).

A tiny synthetic run set whose answers are known by hand: the fastest structure per scene and
ray kind with its margins, paired figures preferred over ratios of medians, a structure the
generator was not told of (a wide BVH) given its own columns, the targets measured, runs of two
machines refused, `check` failing on a page that differs from its JSON, and plot.py's charts of
one ray kind, the run under an ISA cap and the hit buffers of every cap. Then the committed page
against the committed JSON (skipped, with a message, without ../shared).
"""
import copy
import json
import os
import subprocess
import sys
import tempfile
import unittest

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
BENCH = os.path.join(REPO, "bench")
SHARED = os.path.join(REPO, "..", "shared")
sys.path.insert(0, BENCH)

import results_page  # noqa: E402

MACHINE = {"cpu": "Test CPU", "physical_cores": 2, "hardware_threads": 2, "compiler": "gcc 12.2.0",
           "embree_version": "3.13.5"}
STUDY = """# Benchmark conventions

## The reference study's results (Table 2)

| scene | triangles | build BVH | build KD | build Octree | render BVH | render KD | render Octree | Mrays/s BVH | Mrays/s KD | Mrays/s Octree |
| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |
| Simple | 1k | 0.04 | 0.32 | 0.06 | 0.41 | 0.67 | 0.74 | 5.01 | 3.12 | 2.80 |
| Complex | 2k | 2.39 | 12.16 | 3.95 | 4.75 | 2.03 | 13.80 | 0.44 | 1.02 | 0.15 |
"""
SCENES = [{"name": "simple", "kind": "simple"}, {"name": "complex", "kind": "complex"}]


def row(scene, structure, traversal, threads, mrays, rays="primary", **extra):
    r = {"scene": scene, "structure": structure, "traversal": traversal, "threads": threads, "rays": rays,
         "mrays_per_s": mrays, "render_ms": 1000.0 / mrays, "build_ms": 10.0 * threads, "bytes_per_triangle": 64.0,
         "triangles": 1000 if scene == "simple" else 2000, "hit_miss_share": 0.0, "triangle_share": 0.0,
         "max_relative_t_difference": 0.0, "triangle_test": None if structure == "embree" else "watertight",
         "slabs": None if structure == "embree" else "robust", "sweep_value": None, "ratio_to_embree": None,
         "paired_over_embree": None, "paired_over_bvh": None, "paired_over_scalar": None,
         "nodes_per_ray": 10.0, "triangles_per_ray": 2.0}
    r.update(extra)
    return r


def report(rows, width=64, height=36):
    return {"machine": dict(MACHINE), "threads": [1, 2], "width": width, "height": height, "repeats": 5,
            "warmup_runs": 1, "reference": "embree rtcIntersect1", "rows": rows}


def primary_rows():
    """Simple: the BVH fastest (simd8, 40 Mrays/s), the KD-tree 32 (1.25x slower), the Octree 20 (2x).
    Complex: the KD-tree fastest (simd8, 30), the BVH 24 (1.25x), the Octree 10 (3x). A bvh8 on the
    simple scene only, slower than the BVH."""
    speeds = {("simple", "bvh"): 40.0, ("simple", "kdtree"): 32.0, ("simple", "octree"): 20.0,
              ("complex", "bvh"): 24.0, ("complex", "kdtree"): 30.0, ("complex", "octree"): 10.0}
    rows = []
    for (scene, structure), fast in speeds.items():
        for t in (1, 2):
            scale = t / 2.0
            rows.append(row(scene, structure, "scalar", t, fast * scale / 4, paired_over_embree=0.5,
                            paired_over_bvh=None if structure == "bvh" else speeds[(scene, structure)] /
                            speeds[(scene, "bvh")]))
            # Packets: paired with Embree at one thread only, so the two-thread cell is a ratio of medians.
            rows.append(row(scene, structure, "simd8", t, fast * scale, paired_over_scalar=4.0 if t == 1 else 2.5,
                            paired_over_embree=0.8 if t == 1 else None, ratio_to_embree=0.75))
        rows.append(row(scene, "embree", "rtcIntersect1", 2, 30.0))
        rows.append(row(scene, "embree", "rtcIntersect8", 2, 50.0))
    rows.append(row("simple", "bvh", "simd8", 2, 35.0, bvh_width=8, paired_over_embree=0.7))
    return rows


def ray_kind_rows():
    rows = []
    for scene in ("simple", "complex"):
        for t in (1, 2):
            rows.append(row(scene, "bvh", "scalar", t, 10.0))
            rows.append(row(scene, "kdtree", "scalar", t, 8.0))
            # Shadow rays: the Octree is fastest here, at 1.5x its primary rays on the complex scene only.
            rows.append(row(scene, "bvh", "scalar", t, 5.0, rays="shadow", ratio_to_embree=0.9))
            rows.append(row(scene, "octree", "scalar", t, 6.0, rays="shadow"))
            rows.append(row(scene, "octree", "scalar", t, 5.0 if scene == "simple" else 2.0))
    return rows


TARGETS = [
    {"issue": 6, "target": "8 lanes at least 3x scalar", "measure": "speed_ratio", "to": {"traversal": "scalar"},
     "paired": "paired_over_scalar", "at_least": 3.0, "rows": {"traversal": "simd8", "structure": "bvh"},
     "reason": "Why, in words.", "trials": "experiments/packets.md"},
    {"issue": 9, "target": "shadow at least 1.5x primary", "run": "ray_kinds", "measure": "speed_ratio",
     "to": {"rays": "primary"}, "at_least": 1.5, "rows": {"rays": "shadow", "structure": "octree", "threads": 2},
     "reason": "Shadow reason.", "trials": "experiments/shadow-diffuse.md"},
    {"issue": 4, "target": "KD build under 1.5 s", "measure": "value", "column": "build_ms", "unit": "ms",
     "at_most": 1500, "rows": {"structure": "kdtree", "traversal": "scalar", "threads": 1},
     "reason": "-", "trials": "experiments/kdtree.md"},
    {"issue": 3, "target": "scaling", "measure": "value", "column": "speedup_over_one_thread", "at_least": 1.9,
     "rows": {"structure": "bvh"}, "reason": "-", "trials": "experiments/bvh-build.md"},
]


class RunSetFixture(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.addCleanup(self.dir.cleanup)
        self.write("primary.json", report(primary_rows()))
        self.write("ray_kinds.json", report(ray_kind_rows(), 32, 18))
        self.write("BENCHMARK.md", STUDY)
        self.write("scenes.json", SCENES)
        self.write("targets.json", TARGETS)
        self.manifest = {"commit": "abc1234", "dirty": False, "date": "2026-12-02T07:00:00Z",
                         "steps": [{"name": "primary", "seconds": 90, "command": "build/trident-bench ..."}],
                         "runs": [{"name": "primary", "json": "primary.json"},
                                  {"name": "ray_kinds", "json": "ray_kinds.json"}]}
        self.write("run.json", self.manifest)

    def path(self, name):
        return os.path.join(self.dir.name, name)

    def write(self, name, content):
        with open(self.path(name), "w") as f:
            f.write(content if isinstance(content, str) else json.dumps(content))

    def page(self):
        return results_page.page(self.path("run.json"), self.path("BENCHMARK.md"), self.path("scenes.json"),
                                 self.path("targets.json"))

    def section(self, text, heading):
        """From `heading` to the next heading of its level or above."""
        start = text.index(heading)
        level = len(heading) - len(heading.lstrip("#"))
        ends = [text.find("\n" + "#" * n + " ", start + len(heading)) for n in range(2, level + 1)]
        ends = [e for e in ends if e >= 0]
        return text[start:min(ends)] if ends else text[start:]

    def table_row(self, text, first_cell):
        return next(line for line in text.splitlines() if line.startswith("| {} |".format(first_cell)))


class TheStudysQuestion(RunSetFixture):
    def test_the_fastest_structure_per_scene_with_its_margins(self):
        question = self.section(self.page(), "### Primary rays, 2 threads")
        simple = self.table_row(question, "simple").split(" | ")
        self.assertIn("**BVH simd8**", simple)
        self.assertIn("40.0", simple)
        self.assertIn("1.25x (simd8)", simple)  # over the KD-tree
        self.assertIn("2.00x (simd8)", simple)  # over the Octree
        self.assertIn("1.14x (simd8)", simple)  # over the wide BVH's 35
        complex_ = self.table_row(question, "complex").split(" | ")
        self.assertIn("**KD-tree simd8**", complex_)
        self.assertIn("3.00x (simd8)", complex_)
        self.assertIn("Our fastest structure is the study's on 2 of 2 scenes; the Octree is our slowest on 2 of 2. "
                      "The BVH is our fastest on 1 of the 1 simple scenes. "
                      "The KD-tree is our fastest on 1 of the 1 complex scenes.", question)

    def test_every_ray_kind_gets_its_own_table(self):
        shadow = self.section(self.page(), "### Shadow rays, 2 threads")
        self.assertIn("**Octree scalar**", self.table_row(shadow, "simple"))
        self.assertIn("1.20x (scalar)", self.table_row(shadow, "simple"))
        self.assertIn("Our fastest structure is the study's on 0 of 2 scenes", shadow)

    def test_a_structure_it_was_not_told_of_gets_columns(self):
        text = self.page()
        self.assertIn("over BVH-8", text)
        self.assertIn("BVH-8 simd8", self.section(text, "## Ours against Embree"))


class AgainstEmbree(RunSetFixture):
    def test_paired_figures_are_plain_and_ratios_of_medians_are_marked(self):
        embree = self.section(self.page(), "### Primary rays, from")
        header = self.table_row(embree, "scene").split(" | ")
        cells = self.table_row(embree, "simple").split(" | ")
        self.assertEqual(cells[header.index("BVH simd8")], "0.80 / 0.75*")
        self.assertEqual(cells[header.index("BVH scalar")], "0.50 / 0.50")

    def test_shadow_rays_against_embree_when_the_run_has_them(self):
        self.assertIn("### Shadow rays, from", self.page())


class Targets(RunSetFixture):
    def test_targets_measured_from_the_rows(self):
        targets = self.section(self.page(), "## Targets not met")
        packets = self.table_row(targets, "6")
        self.assertIn("2.50–4.00 (paired)", packets)
        self.assertIn("| 2 of 4 |", packets)
        shadow = self.table_row(targets, "9")
        self.assertIn("1.20–3.00 (unpaired)", shadow)  # 6 / 5 on the simple scene, 6 / 2 on the complex one
        self.assertIn("| 1 of 2 | simple |", shadow)
        self.assertIn("Met on this run set: KD build under 1.5 s (issue 4: 10.0 ms)", targets)
        self.assertIn("Not measured by this run set (see the trials): scaling (issue 3", targets)

    def test_a_target_without_a_bound_is_refused(self):
        broken = copy.deepcopy(TARGETS)
        del broken[0]["at_least"]
        self.write("targets.json", broken)
        with self.assertRaises(results_page.PageError):
            self.page()


class RunSets(RunSetFixture):
    def test_runs_of_two_machines_are_refused(self):
        other = report(ray_kind_rows())
        other["machine"]["cpu"] = "Another CPU"
        self.write("ray_kinds.json", other)
        with self.assertRaisesRegex(results_page.PageError, "2 machines"):
            self.page()

    def test_a_missing_json_names_the_file(self):
        os.remove(self.path("ray_kinds.json"))
        with self.assertRaisesRegex(results_page.PageError, "ray_kinds.json"):
            self.page()

    def test_the_page_names_the_commit_and_the_placeholder(self):
        self.manifest.update(dirty=True, placeholder="A quick run.")
        self.write("run.json", self.manifest)
        text = self.page()
        self.assertIn("commit `abc1234` with uncommitted changes", text)
        self.assertIn("> **Placeholder.** A quick run.", text)


class Check(RunSetFixture):
    def check(self, page_path):
        return subprocess.run([sys.executable, os.path.join(BENCH, "summarize.py"), "check", page_path,
                               "--run", self.path("run.json"), "--study-table", self.path("BENCHMARK.md"),
                               "--scenes", self.path("scenes.json"), "--targets", self.path("targets.json")],
                              capture_output=True, text=True)

    def test_check_passes_on_the_page_it_makes_and_fails_on_a_figure_changed(self):
        text = self.page()
        self.write("RESULTS.md", text)
        self.assertEqual(self.check(self.path("RESULTS.md")).returncode, 0)
        self.write("RESULTS.md", text.replace("| 40.0 |", "| 41.0 |", 1))
        failed = self.check(self.path("RESULTS.md"))
        self.assertEqual(failed.returncode, 1)
        self.assertIn("differs", failed.stderr)
        self.assertIn("41.0", failed.stderr)


class Charts(RunSetFixture):
    def plot(self, *args):
        return subprocess.run([sys.executable, os.path.join(BENCH, "plot.py"), self.path("ray_kinds.json"),
                               "--out", self.path("charts")] + list(args), capture_output=True, text=True)

    def test_a_ray_kind_gets_its_fastest_traversal_chart(self):
        try:
            import matplotlib  # noqa: F401
        except ImportError:
            self.skipTest("python3-matplotlib is missing: plot.py not tested")
        done = self.plot("--rays", "shadow")
        self.assertEqual(done.returncode, 0, done.stderr)
        written = sorted(os.path.basename(p) for p in done.stdout.split())
        self.assertEqual(written, ["fastest.png", "mrays.png"])  # no build time for shadow rays, one traversal
        with open(self.path("charts/fastest.png"), "rb") as f:
            self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n")
        missing = self.plot("--rays", "diffuse")
        self.assertNotEqual(missing.returncode, 0)
        self.assertIn("no rows of diffuse rays", missing.stderr)


def portable_rows():
    """The portable build over the native one: the BVH's 4 lanes fast on both scenes, its single rays
    slow on the complex one."""
    rows = []
    for scene, scalar in (("simple", 1.00), ("complex", 0.90)):
        for traversal, ratio in (("scalar", scalar), ("simd4", 1.05)):
            rows.append({"scene": scene, "structure": "bvh", "traversal": traversal, "rays": "primary",
                         "threads": 1, "median": ratio, "min": ratio - 0.01, "max": ratio + 0.01,
                         "ratios": [ratio - 0.01, ratio, ratio + 0.01]})
    return rows


PORTABLE_TARGETS = [
    {"issue": 34, "target": "portable at least 0.97x native", "measure": "portable_ratio", "at_least": 0.97,
     "reason": "Portable reason.", "trials": "experiments/portable_build.md"},
    {"issue": 34, "target": "test under 12 minutes", "measure": "setup_seconds", "command": "bash run.sh test",
     "at_most": 720, "reason": "Test reason.", "trials": "experiments/test_time.md"},
    {"issue": 34, "target": "bench under 5 minutes", "measure": "setup_seconds", "command": "bash run.sh bench",
     "at_most": 300, "reason": "Bench reason.", "trials": "experiments/test_time.md"},
]


class PortableAndSetup(RunSetFixture):
    def setUp(self):
        super().setUp()
        self.write("portable.json", {"rounds": 3, "each_scene": "simple,complex", "machine": dict(MACHINE),
                                     "rows": portable_rows()})
        self.write("setup.json", {"commit": "abc1234", "cpu": MACHINE["cpu"], "hardware_threads": 2,
                                  "commands": [{"command": "bash run.sh test", "seconds": 600},
                                               {"command": "bash run.sh bench", "seconds": 330}]})
        self.write("targets.json", TARGETS + PORTABLE_TARGETS)
        self.manifest.update(portable="portable.json", setup="setup.json")
        self.manifest["steps"].append({"name": "portable", "seconds": 60, "command": "compare_builds.py ..."})
        self.write("run.json", self.manifest)

    def test_the_ratios_per_structure_and_traversal(self):
        portable = self.section(self.page(), "## The portable build against the native one")
        cells = self.table_row(portable, "BVH").split(" | ")
        self.assertEqual(cells[1:], ["0.90–1.00 (0.95)", "1.05 (1.05) |"])
        self.assertIn("Command: `compare_builds.py ...`", portable)
        self.assertIn("4 rows; their medians 0.90–1.05, the median of those 1.02.", portable)

    def test_the_clean_clone_times(self):
        setup = self.section(self.page(), "## What a newcomer waits")
        self.assertIn("| `bash run.sh test` | 10.0 |", setup)
        self.assertIn("| `bash run.sh bench` | 5.5 |", setup)

    def test_the_methods_noise_when_measured(self):
        self.assertNotIn("The method's noise", self.page())
        # The simple scene's rows only: the portable build's are 1.00 and 1.05 there; the complex
        # scene's 0.90 is not compared.
        rows = [dict(row, median=median) for row, median in zip(portable_rows()[:2], (1.03, 1.01))]
        self.write("portable_self.json", {"rounds": 3, "each_scene": "simple", "machine": dict(MACHINE),
                                          "rows": rows})
        self.manifest.update(portable_self="portable_self.json")
        self.manifest["steps"].append({"name": "portable_self", "seconds": 30, "command": "compare_builds.py self"})
        self.write("run.json", self.manifest)
        portable = self.section(self.page(), "## The portable build against the native one")
        self.assertIn("The method's noise: the native build against itself, the same way (3 rounds, scenes "
                      "`simple`): 2 rows, their medians 1.01–1.03; the portable build's rows on those scenes below "
                      "its lowest: 1 of 2. Command: `compare_builds.py self`.", portable)

    def test_their_targets(self):
        targets = self.section(self.page(), "## Targets not met")
        portable = self.table_row(targets, "34")
        self.assertIn("0.90–1.05 (paired) | 3 of 4 | complex |", portable)
        self.assertIn("bench under 5 minutes | 330 s | 0 of 1 | `bash run.sh bench` |", targets)
        self.assertIn("test under 12 minutes (issue 34: 600 s)", targets)

    def test_absent_they_are_not_measured(self):
        del self.manifest["portable"], self.manifest["setup"]
        self.write("run.json", self.manifest)
        text = self.page()
        self.assertIn("Not measured by this run set (its `portable` step did not run).", text)
        self.assertIn("Not measured by this run set (its `setup` step did not run).", text)
        self.assertIn("portable at least 0.97x native (issue 34", self.section(text, "## Targets not met"))

    def test_another_machines_times_are_refused(self):
        self.write("setup.json", {"commit": "abc1234", "cpu": "Another CPU", "hardware_threads": 2, "commands": []})
        with self.assertRaisesRegex(results_page.PageError, "setup.json: measured on Another CPU"):
            self.page()


def python_rows():
    """The module over the C++ render: the BVH's 16 lanes over the target on the complex scene."""
    return [{"scene": scene, "structure": "bvh", "traversal": traversal, "threads": 2, "ratio": ratio,
             "differing_hits": 0}
            for scene, traversal, ratio in (("simple", "scalar", 0.95), ("complex", "scalar", 1.00),
                                            ("simple", "simd16", 1.04), ("complex", "simd16", 1.08))]


class PythonModule(RunSetFixture):
    def setUp(self):
        super().setUp()
        self.write("python.json", {"width": 1920, "height": 1080, "rounds": 3, "repeats": 3,
                                   "machine": dict(MACHINE), "rows": python_rows()})
        self.write("targets.json", TARGETS + [
            {"issue": 33, "target": "module at most 1.05x C++", "measure": "python_ratio", "at_most": 1.05,
             "reason": "Python reason.", "trials": "experiments/python_module.md"}])
        self.manifest.update(python="python.json")
        self.manifest["steps"].append({"name": "python", "seconds": 60, "command": "python_bench.py ..."})
        self.write("run.json", self.manifest)

    def test_the_ratios_per_structure_and_traversal(self):
        section = self.section(self.page(), "## The Python module against the C++ renderer")
        self.assertEqual(self.table_row(section, "BVH").split(" | ")[1:], ["0.95–1.00 (0.97)", "1.04–1.08 (1.06) |"])
        self.assertIn("2 threads (1920x1080)", section)
        self.assertIn("differs from trident-bench's hit buffer of the same rays: 0. Command: `python_bench.py ...`.",
                      section)

    def test_its_target(self):
        row = self.table_row(self.section(self.page(), "## Targets not met"), "33")
        self.assertIn("0.95–1.08 (paired) | 3 of 4 | complex |", row)

    def test_absent_it_is_not_measured(self):
        del self.manifest["python"]
        self.write("run.json", self.manifest)
        text = self.page()
        self.assertIn("Not measured by this run set (its `python` step did not run).", text)
        self.assertIn("module at most 1.05x C++ (issue 33", self.section(text, "## Targets not met"))


def avx2_rows():
    """Under the AVX2 cap, paired with Embree at AVX2: single rays ahead on both scenes, 8-lane shadow
    packets behind on the complex one."""
    rows = []
    for scene in ("simple", "complex"):
        for rays in ("primary", "shadow"):
            rows.append(row(scene, "bvh", "scalar", 1, 10.0, rays=rays, paired_over_embree=1.10))
            rows.append(row(scene, "bvh", "simd8", 1, 20.0, rays=rays,
                            paired_over_embree=0.90 if (scene, rays) == ("complex", "shadow") else 1.05))
        rows.append(row(scene, "embree", "rtcIntersect1", 1, 9.0))
    return rows


def caps_rows():
    """Hit buffers under two caps: one octree buffer differs in 3 rays under sse4."""
    rows = []
    for scene in ("simple", "complex"):
        for structure in ("bvh", "octree"):
            for cap, traversals in (("sse4", ("scalar", "simd4")), ("avx2", ("scalar", "simd4", "simd8"))):
                for traversal in traversals:
                    differ = 3 if (scene, structure, cap, traversal) == ("complex", "octree", "sse4", "simd4") else 0
                    rows.append({"scene": scene, "structure": structure, "traversal": traversal, "cap": cap,
                                 "rays": 1000, "differing_rays": differ})
    return rows


class IsaCaps(RunSetFixture):
    def setUp(self):
        super().setUp()
        avx2 = report(avx2_rows(), 32, 18)
        avx2.update(threads=[1], isa_cap="avx2", embree_isa="avx2")
        self.write("avx2.json", avx2)
        self.write("caps.json", {"tool": "compare_caps.py", "machine": dict(MACHINE), "width": 64, "height": 36,
                                 "rows": caps_rows(), "skipped": [{"cap": "avx512", "why": "no AVX-512 here"}]})
        self.write("targets.json", TARGETS + [
            {"issue": 34, "target": "avx2 at least Embree avx2", "run": "avx2", "measure": "speed_ratio",
             "to": {"structure": "embree"}, "paired": "paired_over_embree", "at_least": 1.0,
             "rows": {"structure": "bvh", "traversals": ["scalar", "simd8"]}, "reason": "AVX2 reason.",
             "trials": "experiments/portable_build.md"},
            {"issue": 34, "target": "identical hit buffers", "measure": "caps_differing", "at_most": 0,
             "reason": "Caps reason.", "trials": "experiments/portable_build.md"}])
        self.manifest["runs"].append({"name": "avx2", "json": "avx2.json"})
        self.manifest.update(caps="caps.json")
        self.manifest["steps"] += [{"name": "avx2", "seconds": 60, "command": "env TRIDENT_ISA=avx2 trident-bench ..."},
                                   {"name": "caps", "seconds": 60, "command": "compare_caps.py ..."}]
        self.write("run.json", self.manifest)

    def test_ours_against_embree_at_the_same_cap(self):
        section = self.section(self.page(), "## AVX2 as our users have it")
        self.assertIn("`TRIDENT_ISA=avx2`", section)
        self.assertIn("(`max_isa=avx2`)", section)
        self.assertIn("Command: `env TRIDENT_ISA=avx2 trident-bench ...`.", section)
        header = next(line for line in section.splitlines() if line.startswith("| scene |"))
        self.assertEqual(header, "| scene | BVH scalar, primary | BVH scalar, shadow | BVH simd8, primary | "
                                 "BVH simd8, shadow |")
        self.assertEqual(self.table_row(section, "complex"), "| complex | 1.10 | 1.10 | 1.05 | 0.90 |")

    def test_the_hit_buffers_per_structure_and_cap(self):
        section = self.section(self.page(), "## The same hits under every instruction set")
        self.assertIn("| BVH | 0 of 4 (0 rays) | 0 of 6 (0 rays) |", section)
        self.assertIn("| Octree | 1 of 4 (3 rays) | 0 of 6 (0 rays) |", section)
        self.assertIn("Not run under `avx512` on this CPU: no AVX-512 here", section)
        self.assertIn("Command: `compare_caps.py ...`.", section)

    def test_their_targets(self):
        targets = self.section(self.page(), "## Targets not met")
        self.assertIn("| avx2 at least Embree avx2 | 0.90–1.10 (paired) | 7 of 8 | complex |", targets)
        self.assertIn("| identical hit buffers | 1 of 20 hit buffers differ | 19 of 20 | complex |", targets)

    def test_absent_they_are_not_measured(self):
        self.manifest["runs"].pop()
        del self.manifest["caps"]
        self.write("run.json", self.manifest)
        text = self.page()
        self.assertIn("Not measured by this run set (its `avx2` step did not run).", text)
        self.assertIn("Not measured by this run set (its `caps` step did not run).", text)
        self.assertIn("identical hit buffers (issue 34", self.section(text, "## Targets not met"))


class TheCommittedPage(unittest.TestCase):
    def test_bench_results_md_is_what_its_json_gives(self):
        if not os.path.exists(os.path.join(SHARED, "BENCHMARK.md")):
            self.skipTest("../shared is absent: the page quotes the study's Table 2 from it")
        done = subprocess.run([sys.executable, os.path.join(BENCH, "summarize.py"), "check",
                               os.path.join(BENCH, "RESULTS.md")], capture_output=True, text=True)
        self.assertEqual(done.returncode, 0, done.stderr)


if __name__ == "__main__":
    unittest.main()
