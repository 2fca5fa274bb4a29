"""Detection rates of `bondgraph discover` over seeded synthetic data sets, for the systems
with an independent reference generator: two_tank, thermal, actuator.

For each hidden effect of SYSTEM/data/generate.py (and for nothing hidden), draws `--seeds`
data sets (generate.py --seed K --hidden ID, K = 101, 102, ... or from `--first`; the parameter drawn in the
seeded range its data/README.md gives), hands each to `bondgraph discover --format json` with
the system's experiment and extension library, on the steady sweep and on the two runs, and
counts the verdicts a correct answer gives:

- a real cause: selected, or reported indistinguishable from the selection;
- the refit in disguise: nothing selected, and the id reported indistinguishable from the
  base model ("aliased with the base", or listed in `indistinguishable`);
- nothing hidden: nothing selected.

A discover that fails, or a data set generate.py cannot make, counts as a miss, and its first
error line is kept.

Run from the repository root after `cargo build --release`, with numpy and scipy (the
versions of SYSTEM/data/requirements.txt):

    python3 models/examples/detection_rates.py SYSTEM [--seeds 20] [--first 101] [--kind steady|step|both]
        [--jobs N] [--json FILE] [--only ID,...]

It prints a Markdown table: one row per hidden id, one column per kind, `found/seeds`, with
the median seconds of one discover.
"""

import argparse
import concurrent.futures
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

EXAMPLES = os.path.dirname(os.path.abspath(__file__))

# What each system's files are called, and which candidate is the refit in disguise.
SYSTEMS = {
    "two_tank": ("two_tank.ron", ("experiment.ron", "experiment_step.ron"), "pipe-fouling"),
    "actuator": ("actuator.ron", ("experiment.ron", "experiment_step.ron"), "guide-seal-drag"),
    "thermal": ("thermal.lg.ron", ("experiment.ron", "experiment_step.ron"), "contact-resistance"),
}


def discover(binary, folder, model, experiment, data):
    command = [binary, "discover", "--model", os.path.join(folder, model), "--experiment",
               os.path.join(folder, experiment), "--extensions", os.path.join(folder, "extensions"),
               "--format", "json"]
    for path in data:
        command += ["--data", path]
    start = time.perf_counter()
    result = subprocess.run(command, capture_output=True, text=True)
    seconds = time.perf_counter() - start
    if result.returncode != 0:
        lines = result.stderr.strip().splitlines()
        return None, (lines[0] if lines else "failed"), seconds
    return json.loads(result.stdout), None, seconds


def correct(report, hidden, refit):
    selected = report.get("selected")
    if hidden == "none":
        return selected is None
    verdicts = {c["id"]: c.get("verdict") for c in report.get("candidates", []) if "id" in c}
    if hidden == refit:
        return selected is None and (hidden in report.get("indistinguishable", [])
                                     or verdicts.get(hidden) == "aliased with the base")
    return selected == hidden or hidden in report.get("indistinguishable", [])


def one(args):
    """Generates one seeded data set and runs discover on each kind asked for."""
    system, binary, hidden, seed, kinds, tmp = args
    model, experiments, refit = SYSTEMS[system]
    folder = os.path.join(EXAMPLES, system)
    out = os.path.join(tmp, f"{hidden}-{seed}")
    made = subprocess.run([sys.executable, os.path.join(folder, "data", "generate.py"), "--seed",
                           str(seed), "--hidden", hidden, "--out", out], capture_output=True, text=True)
    if made.returncode != 0:
        # A data set that could not be made is a miss with its reason, not the end of the study.
        lines = made.stderr.strip().splitlines()
        error = f"generate.py failed: {lines[-1] if lines else made.returncode}"
        return hidden, seed, {k: {"correct": False, "selected": None, "error": error, "seconds": 0.0}
                              for k in kinds}
    results = {}
    for kind in kinds:
        experiment = experiments[0] if kind == "steady" else experiments[1]
        data = [os.path.join(out, "steady.csv")] if kind == "steady" else \
            [os.path.join(out, "step_1.csv"), os.path.join(out, "step_2.csv")]
        report, error, seconds = discover(binary, folder, model, experiment, data)
        results[kind] = {
            "correct": bool(report is not None and correct(report, hidden, refit)),
            "selected": None if report is None else report.get("selected"),
            "error": error,
            "seconds": seconds,
        }
    return hidden, seed, results


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("system", choices=sorted(SYSTEMS))
    parser.add_argument("--binary", default="target/release/bondgraph")
    parser.add_argument("--seeds", type=int, default=20)
    parser.add_argument("--first", type=int, default=101,
                        help="the first seed (to add seeds to a table measured before)")
    parser.add_argument("--kind", choices=["steady", "step", "both"], default="both")
    parser.add_argument("--jobs", type=int, default=1)
    parser.add_argument("--json", help="write every run's outcome to this file")
    parser.add_argument("--only", help="comma-separated hidden ids (and `none`) to run, all by default")
    args = parser.parse_args()
    kinds = ["steady", "step"] if args.kind == "both" else [args.kind]
    sys.path.insert(0, os.path.join(EXAMPLES, args.system, "data"))
    import generate  # noqa: E402
    hidden_ids = list(generate.COMMITTED) + ["none"]
    if args.only:
        wanted = args.only.split(",")
        unknown = [h for h in wanted if h not in hidden_ids]
        if unknown:
            parser.error(f"--only: unknown hidden id {unknown[0]} (known: {', '.join(hidden_ids)})")
        hidden_ids = [h for h in hidden_ids if h in wanted]
    with tempfile.TemporaryDirectory() as tmp:
        work = [(args.system, args.binary, h, s, kinds, tmp)
                for h in hidden_ids for s in range(args.first, args.first + args.seeds)]
        outcomes = []
        with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
            for hidden, seed, results in pool.map(one, work):
                outcomes.append((hidden, seed, results))
                said = ", ".join(f"{k}: {'found' if r['correct'] else 'missed'}"
                                 f"{' (' + r['error'] + ')' if r['error'] else ''}"
                                 for k, r in results.items())
                print(f"{hidden} seed {seed}: {said}", file=sys.stderr, flush=True)
    print(f"| hidden ({args.system}, {args.seeds} seeds) | " + " | ".join(kinds) + " |")
    print("|---|" + "---|" * len(kinds))
    for hidden in hidden_ids:
        cells = []
        for kind in kinds:
            runs = [r[kind] for h, _, r in outcomes if h == hidden]
            found = sum(r["correct"] for r in runs)
            errors = sorted({r["error"] for r in runs if r["error"]})
            seconds = statistics.median(r["seconds"] for r in runs)
            cell = f"{found}/{len(runs)} ({seconds:.1f} s)"
            if errors:
                cell += f"; {sum(1 for r in runs if r['error'])} failed: {errors[0]}"
            cells.append(cell)
        print(f"| `{hidden}` | " + " | ".join(cells) + " |")
    if args.json:
        with open(args.json, "w") as f:
            json.dump([{"hidden": h, "seed": s, **r} for h, s, r in outcomes], f, indent=1)


if __name__ == "__main__":
    main()
