"""Compares `bondgraph simulate` with this folder's independent reference (generate.py).

For the base model and each extension at the hidden values generate.py uses, the script
writes the model with the truth's values (the extension merged by `bondgraph extend`), a
scenario whose pump flow is run 1's and run 2's recorded signal (a Table: the straight line
through the 1 s samples, as generate.py integrates it), runs `bondgraph simulate`, and prints
the largest difference from generate.py's noise-free series on each observed column.

Run from the repository root after `cargo build --release`:
    python3 models/examples/two_tank/data/compare_with_reference.py [--binary target/release/bondgraph]
Exits non-zero when a difference exceeds the tolerance (1e-6 mm of level, 1e-6 mL/s).
"""

import argparse
import csv
import io
import os
import re
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import generate as reference  # noqa: E402

MODEL = os.path.join(HERE, "..", "two_tank.ron")
EXTENSIONS = os.path.join(HERE, "..", "extensions")
TOLERANCE = 1e-6


def with_values(text, values):
    """The model text with each named parameter's value replaced."""
    for name, value in values.items():
        text, count = re.subn(r'("%s":\s*\(value:\s*)[-+0-9.eE]+' % re.escape(name),
                              lambda m: m.group(1) + repr(float(value)), text)
        if count != 1:
            raise SystemExit(f"parameter {name} not found once in the model")
    return text


def scenario(times, recorded):
    points = ", ".join(f"({float(t)!r}, {1e-6 * float(u)!r})" for t, u in zip(times, recorded))
    h0 = reference.A_1 * reference.H0
    return f"""Scenario(
    name: "reference",
    inputs: {{ "Q_p": Table([{points}]) }},
    initial_state: {{ "tank_1": {h0!r}, "tank_2": {reference.A_2 * reference.H0!r} }},
    duration: {float(times[-1])!r},
    record: ["effort:tank_1", "effort:tank_2", "flow:outlet"],
    sample: {reference.SAMPLE!r},
)
"""


def simulate(binary, model_path, scenario_path):
    out = subprocess.run([binary, "simulate", model_path, "--scenario", scenario_path],
                         check=True, capture_output=True, text=True).stdout
    rows = list(csv.DictReader(io.StringIO(out)))
    column = lambda name: np.array([float(r[name]) for r in rows])  # noqa: E731
    return column("t"), column("effort:tank_1"), column("effort:tank_2"), column("flow:outlet")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--binary", default="target/release/bondgraph")
    args = parser.parse_args()
    cases = [("base", None)] + [(h, h) for h in sorted(reference.HIDDEN)]
    worst = 0.0
    with tempfile.TemporaryDirectory() as tmp:
        for label, hidden in cases:
            model_path = os.path.join(tmp, f"{label}.ron")
            if hidden is None:
                text = open(MODEL).read()
                p = reference.parameters()
                values = dict(reference.TRUTH)
            else:
                subprocess.run([args.binary, "extend", MODEL,
                                os.path.join(EXTENSIONS, hidden + ".ron"), "--out", model_path],
                               check=True, capture_output=True)
                text = open(model_path).read()
                name, value, _ = reference.HIDDEN[hidden]
                p = reference.parameters(hidden, value)
                values = dict(reference.TRUTH, **{name: value})
            with open(model_path, "w") as f:
                f.write(with_values(text, values))
            for run, command in reference.RUNS:
                times, recorded, h_1, h_2, outlet = reference.series(p, command)
                scenario_path = os.path.join(tmp, "scenario.ron")
                with open(scenario_path, "w") as f:
                    f.write(scenario(times, recorded))
                t, p_1, p_2, q = simulate(args.binary, model_path, scenario_path)
                assert len(t) == len(times) and np.allclose(t, times)
                rho_g = reference.RHO * reference.G
                d = [np.max(np.abs(1e3 * p_1 / rho_g - 1e3 * h_1)),
                     np.max(np.abs(1e3 * p_2 / rho_g - 1e3 * h_2)),
                     np.max(np.abs(1e6 * q - 1e6 * outlet))]
                worst = max(worst, *d)
                print(f"{label:22s} {run:11s} max |bondgraph - reference|: h_1 {d[0]:.2e} mm, "
                      f"h_2 {d[1]:.2e} mm, Q_out {d[2]:.2e} mL/s")
    print(f"largest difference {worst:.2e} (tolerance {TOLERANCE:g})")
    sys.exit(0 if worst <= TOLERANCE else 1)


if __name__ == "__main__":
    main()
