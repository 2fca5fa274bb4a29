"""Detection rates of `bondgraph discover` over seeded synthetic data sets.

For each hidden effect of generate.py (and for nothing hidden), draws `--seeds` data sets
(generate.py --seed K --hidden ID, K = 101, 102, ...), hands each to `bondgraph discover
--format json` with this system's experiment and extension library, once on the steady sweep
and once on the two runs, and counts the verdicts a correct answer gives:

- a real cause: selected, or reported indistinguishable from the selection;
- the refit in disguise: nothing selected, and the id reported indistinguishable from the
  base model ("aliased with the base", or listed in `indistinguishable`);
- nothing hidden: nothing selected.

Run from the repository root after `cargo build --release` (slow: one discover per seed):
    python3 models/examples/SYSTEM/data/detection_rates.py (SYSTEM: two_tank, actuator, thermal) [--seeds 20] [--kind steady|step|both]
It prints one line per hidden id and kind; a discover that fails prints its error once.
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
FOLDER = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import generate  # noqa: E402

# What this system's files are called, and which candidate is the refit in disguise.
SYSTEM = {
    "two_tank": ("two_tank.ron", "extensions", ("experiment.ron", "experiment_step.ron"), "pipe-fouling"),
    "actuator": ("actuator.ron", "extensions", ("experiment.ron", "experiment_step.ron"), "guide-seal-drag"),
    "thermal": ("thermal.lg.ron", "extensions", ("experiment.ron", "experiment_step.ron"), "contact-resistance"),
}[os.path.basename(FOLDER)]


def discover(binary, data, experiment):
    command = [binary, "discover", "--model", os.path.join(FOLDER, SYSTEM[0]), "--experiment",
               os.path.join(FOLDER, experiment), "--extensions", os.path.join(FOLDER, SYSTEM[1]),
               "--format", "json"]
    for path in data:
        command += ["--data", path]
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode != 0:
        return None, result.stderr.strip().splitlines()[0] if result.stderr.strip() else "failed"
    return json.loads(result.stdout), None


def correct(report, hidden):
    selected = report.get("selected")
    if hidden == "none":
        return selected is None
    verdicts = {c["id"]: c.get("verdict") for c in report.get("candidates", []) if "id" in c}
    if hidden == SYSTEM[3]:
        return selected is None and (hidden in report.get("indistinguishable", [])
                                     or verdicts.get(hidden) == "aliased with the base")
    return selected == hidden or hidden in report.get("indistinguishable", [])


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--binary", default="target/release/bondgraph")
    parser.add_argument("--seeds", type=int, default=20)
    parser.add_argument("--kind", choices=["steady", "step", "both"], default="both")
    args = parser.parse_args()
    kinds = ["steady", "step"] if args.kind == "both" else [args.kind]
    hidden_ids = [h for h in generate.COMMITTED] + ["none"]
    with tempfile.TemporaryDirectory() as tmp:
        for kind in kinds:
            experiment = SYSTEM[2][0] if kind == "steady" else SYSTEM[2][1]
            for hidden in hidden_ids:
                found, errors = 0, set()
                for seed in range(101, 101 + args.seeds):
                    out = os.path.join(tmp, f"{hidden}-{seed}")
                    subprocess.run([sys.executable, os.path.join(HERE, "generate.py"), "--seed", str(seed),
                                    "--hidden", hidden, "--out", out], check=True, capture_output=True)
                    data = [os.path.join(out, "steady.csv")] if kind == "steady" else \
                        [os.path.join(out, "step_1.csv"), os.path.join(out, "step_2.csv")]
                    report, error = discover(args.binary, data, experiment)
                    if error is not None:
                        errors.add(error)
                        break
                    found += correct(report, hidden)
                if errors:
                    print(f"{kind:6s} {hidden:26s} discover failed: {sorted(errors)[0]}")
                else:
                    print(f"{kind:6s} {hidden:26s} {found}/{args.seeds}")


if __name__ == "__main__":
    main()
