#!/usr/bin/python3
"""Two trident-bench binaries on the same rows, in turn, and each row's speed ratio round by round.

    /usr/bin/python3 bench/compare_builds.py build-portable/trident-bench build/trident-bench \\
        --rounds 3 --markdown out.md -- --scenes ../shared/scenes/scenes.json --threads 1 ...

Each round runs both binaries with the same arguments (and so the same scenes, camera and rays),
the order alternating from pair to pair (A B, B A, A B, ...) so that neither binary always runs
on a warmer or a quieter machine. With --each-scene and --each-accel a round is one pair of runs
per scene and structure (--only SCENE --accel NAME added), so the two runs of a pair are seconds
apart, not minutes, and a drift of the machine's speed falls on both. For every row both runs have (scene, structure, traversal, ray
kind, threads, tests), the round's ratio is A's speed over B's: B's median render time over A's.
The table gives the median of those ratios and their range; over 1 means A is faster. What each
binary printed goes to its --json file only; the command lines and the CPU head the table.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

KEY = ("scene", "structure", "traversal", "rays", "threads", "triangle_test", "slabs")


def run(binary, args, json_path):
    command = [binary] + args + ["--quiet", "--json", json_path]
    done = subprocess.run(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if done.returncode != 0:
        sys.exit("compare_builds.py: {} failed ({}): {}".format(" ".join(command), done.returncode,
                                                                 done.stderr.strip()))
    with open(json_path) as f:
        return json.load(f)


def rows_by_key(report):
    return {tuple(row.get(k) for k in KEY): row for row in report["rows"] if row.get("render_ms")}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                     usage="%(prog)s A B [--rounds N] [--markdown FILE] [--json FILE] -- BENCH_ARGS...")
    parser.add_argument("a", help="binary A (its speed is the numerator)")
    parser.add_argument("b", help="binary B")
    parser.add_argument("--rounds", type=int, default=3, help="rounds of both binaries (default 3)")
    parser.add_argument("--markdown", help="write the table here too")
    parser.add_argument("--json", help="write the rows' ratios here as JSON (bench/results_page.py reads it)")
    parser.add_argument("--each-scene", default="", help="scenes, comma separated: one pair of runs each (--only)")
    parser.add_argument("--each-accel", default="", help="structures, comma separated: one pair of runs each (--accel)")
    # trident-bench's arguments follow "--"; split by hand, as argparse's REMAINDER after
    # positionals would take this script's own options too.
    argv = sys.argv[1:]
    split = argv.index("--") if "--" in argv else len(argv)
    args = parser.parse_args(argv[:split])
    bench_args = argv[split + 1:]
    if args.rounds < 1:
        sys.exit("compare_builds.py: --rounds must be at least 1")
    for binary in (args.a, args.b):
        if not os.access(binary, os.X_OK):
            sys.exit("compare_builds.py: {}: not an executable".format(binary))

    scenes = [["--only", name] for name in args.each_scene.split(",") if name] or [[]]
    accels = [["--accel", name] for name in args.each_accel.split(",") if name] or [[]]
    groups = [scene + accel for scene in scenes for accel in accels]

    ratios, machine, pair = {}, None, 0
    with tempfile.TemporaryDirectory() as scratch:
        for r in range(args.rounds):
            for group in groups:
                order = (("a", args.a), ("b", args.b)) if pair % 2 == 0 else (("b", args.b), ("a", args.a))
                pair += 1
                reports = {}
                for name, binary in order:
                    print("round {}: {} {}".format(r + 1, binary, " ".join(group)), file=sys.stderr, flush=True)
                    reports[name] = run(binary, bench_args + group, os.path.join(scratch, name + ".json"))
                machine = machine or reports["a"].get("machine")
                a_rows, b_rows = rows_by_key(reports["a"]), rows_by_key(reports["b"])
                for key in a_rows.keys() & b_rows.keys():
                    ratios.setdefault(key, []).append(b_rows[key]["render_ms"] / a_rows[key]["render_ms"])
    if not ratios:
        sys.exit("compare_builds.py: the two binaries have no timed row in common")

    each = " ".join(x for x in ("--each-scene " + args.each_scene if args.each_scene else "",
                                "--each-accel " + args.each_accel if args.each_accel else "") if x)
    lines = ["A: `{}`, B: `{}`, {} rounds{}, arguments `{}`".format(
                 args.a, args.b, args.rounds, ", " + each if each else "", " ".join(bench_args)),
             "", "CPU: {}".format((machine or {}).get("cpu", "unknown")), "",
             "| scene | structure | traversal | rays | threads | A over B (median) | min | max |",
             "|---|---|---|---|---|---|---|---|"]
    medians, rows = [], []
    for key in sorted(ratios, key=lambda k: tuple(str(x) for x in k)):
        values = ratios[key]
        medians.append(statistics.median(values))
        lines.append("| {} | {} | {} | {} | {} | {:.3f} | {:.3f} | {:.3f} |".format(
            key[0], key[1], key[2], key[3], key[4], medians[-1], min(values), max(values)))
        rows.append(dict(zip(KEY, key), median=medians[-1], min=min(values), max=max(values), ratios=values))
    lines += ["", "{} rows; the rows' medians range {:.3f} to {:.3f}, their median {:.3f}.".format(
        len(medians), min(medians), max(medians), statistics.median(medians))]
    text = "\n".join(lines) + "\n"
    sys.stdout.write(text)
    if args.markdown:
        with open(args.markdown, "w") as f:
            f.write(text)
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"a": args.a, "b": args.b, "rounds": args.rounds, "each_scene": args.each_scene,
                       "each_accel": args.each_accel, "arguments": bench_args, "machine": machine, "rows": rows},
                      f, indent=2)
            f.write("\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
