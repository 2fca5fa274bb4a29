"""Compares `bondgraph simulate` with this folder's independent reference (generate.py).

The base model is simulated both as the linear graph (thermal.lg.ron) and as its bond-graph
twin (thermal.ron); each hidden effect as the twin with its fragment from
extensions_bond_graph/ merged by `bondgraph extend` (linear graphs take no extensions yet),
the parameter at generate.py's hidden value. The inputs are run 1's and run 2's recorded
heater powers and room temperature (Tables: the straight lines through the 20 s samples, as
generate.py integrates them). The script prints the largest difference from generate.py's
noise-free series on each temperature, and also checks that the two files derive the same
A and B.

Run from the repository root after `cargo build --release`:
    python3 models/examples/thermal/data/compare_with_reference.py [--binary target/release/bondgraph]
Exits non-zero when a difference exceeds 1e-6 K.
"""

import argparse
import csv
import io
import json
import os
import re
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import generate as reference  # noqa: E402

FOLDER = os.path.join(HERE, "..")
TOLERANCE = 1e-6


def with_values(text, values):
    """The text with each named parameter's value replaced."""
    for name, value in values.items():
        text, count = re.subn(r'("%s":\s*\(value:\s*)[-+0-9.eE]+' % re.escape(name),
                              lambda m: m.group(1) + repr(float(value)), text)
        if count != 1:
            raise SystemExit(f"parameter {name} not found once")
    return text


def scenario(times, recorded, records):
    table = lambda k: ", ".join(f"({float(t)!r}, {float(u[k])!r})" for t, u in zip(times, recorded))  # noqa: E731
    return f"""Scenario(
    name: "reference",
    inputs: {{ "P_1": Table([{table(0)}]), "P_2": Table([{table(1)}]), "T_amb": Table([{table(2)}]) }},
    duration: {float(times[-1])!r},
    record: [{", ".join(f'"{r}"' for r in records)}],
    sample: {reference.SAMPLE!r},
)
"""


def run(binary, *args):
    return subprocess.run([binary, *args], check=True, capture_output=True, text=True).stdout


def matrices(binary, path, states):
    doc = json.loads(run(binary, "equations", path, "--states", states, "--format", "json"))
    return np.array(doc["A_value"], dtype=float), np.array(doc["B_value"], dtype=float)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--binary", default="target/release/bondgraph")
    args = parser.parse_args()
    lg, bg = os.path.join(FOLDER, "thermal.lg.ron"), os.path.join(FOLDER, "thermal.ron")
    a_lg, b_lg = matrices(args.binary, lg, "coenergy")
    a_bg, b_bg = matrices(args.binary, bg, "coenergy")
    same = np.allclose(a_lg, a_bg, rtol=1e-14) and np.allclose(b_lg, b_bg, rtol=1e-14)
    print(f"thermal.lg.ron and thermal.ron derive the same A and B: {same}")
    # (label, model file, extension or None, records, sign of the records)
    cases = [("base (linear graph)", lg, None, ["across:heater_1", "across:heater_2"], -1.0),
             ("base (bond graph)", bg, None, ["effort:heater_1", "effort:heater_2"], 1.0)]
    cases += [(h, bg, h, ["effort:heater_1", "effort:heater_2"], 1.0) for h in sorted(reference.HIDDEN)]
    worst = 0.0
    with tempfile.TemporaryDirectory() as tmp:
        for label, model, hidden, records, sign in cases:
            model_path = os.path.join(tmp, "model.ron")
            values = dict(reference.TRUTH)
            if hidden is None:
                text = open(model).read()
                p = reference.parameters()
            else:
                name, value, _ = reference.HIDDEN[hidden]
                p = reference.parameters(hidden, value)
                # The fragment with its parameter at the hidden value: a series resistance of
                # zero (the contact's no-effect value) is refused (see data/README.md).
                fragment = os.path.join(tmp, "fragment.ron")
                with open(fragment, "w") as f:
                    f.write(with_values(open(os.path.join(FOLDER, "extensions_bond_graph", hidden + ".ron")).read(),
                                        {name: value}))
                run(args.binary, "extend", model, fragment, "--out", model_path)
                text = open(model_path).read()
            with open(model_path, "w") as f:
                f.write(with_values(text, values))
            for run_name, command in reference.RUNS:
                times, recorded, t_1, t_2 = reference.series(p, command)
                scenario_path = os.path.join(tmp, "scenario.ron")
                with open(scenario_path, "w") as f:
                    f.write(scenario(times, recorded, records))
                rows = list(csv.DictReader(io.StringIO(run(args.binary, "simulate", model_path,
                                                           "--scenario", scenario_path))))
                t = np.array([float(r["t"]) for r in rows])
                assert len(t) == len(times) and np.allclose(t, times)
                y_1 = sign * np.array([float(r[records[0]]) for r in rows])
                y_2 = sign * np.array([float(r[records[1]]) for r in rows])
                d = (np.max(np.abs(y_1 - t_1)), np.max(np.abs(y_2 - t_2)))
                worst = max(worst, *d)
                print(f"{label:22s} {run_name:11s} max |bondgraph - reference|: T1 {d[0]:.2e} K, T2 {d[1]:.2e} K")
    print(f"largest difference {worst:.2e} K (tolerance {TOLERANCE:g})")
    sys.exit(0 if worst <= TOLERANCE and same else 1)


if __name__ == "__main__":
    main()
