"""Compares `bondgraph simulate` with this folder's independent reference (generate.py).

For the base model and each extension at the hidden values generate.py uses, the script
writes the model with the truth's values (the extension merged by `bondgraph extend`), a
scenario whose voltage and load force are run 1's and run 2's recorded signals (Tables: the
straight lines through the 1 ms samples, as generate.py integrates them), runs `bondgraph
simulate`, and prints the largest difference from generate.py's noise-free series on each
observed column, and the mode switches of both.

Run from the repository root after `cargo build --release`:
    python3 models/examples/actuator/data/compare_with_reference.py [--binary target/release/bondgraph]
Exits non-zero when a difference exceeds the tolerance (1e-4 mm/s of speed, 1e-3 mA).
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

MODEL = os.path.join(HERE, "..", "actuator.ron")
EXTENSIONS = os.path.join(HERE, "..", "extensions")
SPEED_TOLERANCE, CURRENT_TOLERANCE = 1e-4, 1e-3


def with_values(text, values):
    """The model text with each named parameter's value replaced."""
    for name, value in values.items():
        text, count = re.subn(r'("%s":\s*\(value:\s*)[-+0-9.eE]+' % re.escape(name),
                              lambda m: m.group(1) + repr(float(value)), text)
        if count != 1:
            raise SystemExit(f"parameter {name} not found once in the model")
    return text


def scenario(times, recorded):
    voltage = ", ".join(f"({float(t)!r}, {float(u[0])!r})" for t, u in zip(times, recorded))
    load = ", ".join(f"({float(t)!r}, {float(u[1])!r})" for t, u in zip(times, recorded))
    return f"""Scenario(
    name: "reference",
    inputs: {{ "V": Table([{voltage}]), "F_L": Table([{load}]) }},
    initial_mode: "guide=stuck",
    duration: {float(times[-1])!r},
    record: ["flow:carriage", "flow:winding_inductance"],
    sample: {reference.SAMPLE!r},
)
"""


def simulate(binary, model_path, scenario_path):
    out = subprocess.run([binary, "simulate", model_path, "--scenario", scenario_path, "--format", "json"],
                         check=True, capture_output=True, text=True).stdout
    return json.loads(out)


def columns(result):
    """The recorded outputs at the sample times (events add samples of their own)."""
    step = reference.SAMPLE
    samples = [s for s in result["samples"] if abs(s["t"] / step - round(s["t"] / step)) < 1e-6]
    t = np.array([s["t"] for s in samples])
    v = np.array([s["values"]["flow:carriage"] for s in samples])
    i = np.array([s["values"]["flow:winding_inductance"] for s in samples])
    return t, v, i


def events(result):
    return [f"{e['t']:.6f} s {e['from'].split('=')[1]}->{e['to'].split('=')[1]}" for e in result["events"]]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--binary", default="target/release/bondgraph")
    args = parser.parse_args()
    cases = [("base", None)] + [(h, h) for h in sorted(reference.HIDDEN)]
    worst_v = worst_i = 0.0
    with tempfile.TemporaryDirectory() as tmp:
        for label, hidden in cases:
            model_path = os.path.join(tmp, f"{label}.ron")
            if hidden is None:
                text = open(MODEL).read()
                p = reference.parameters()
                values = dict(reference.TRUTH)
            else:
                name, value, _ = reference.HIDDEN[hidden]
                # The extension with its parameter at the hidden value: the Stribeck contact
                # refuses its no-effect value v_s = 0 (see data/README.md).
                fragment = os.path.join(tmp, hidden + ".ron")
                with open(fragment, "w") as f:
                    f.write(with_values(open(os.path.join(EXTENSIONS, hidden + ".ron")).read(),
                                        {name: value}))
                subprocess.run([args.binary, "extend", MODEL, fragment, "--out", model_path],
                               check=True, capture_output=True)
                text = open(model_path).read()
                p = reference.parameters(hidden, value)
                values = dict(reference.TRUTH, **{name: value})
            with open(model_path, "w") as f:
                f.write(with_values(text, values))
            for run, command in reference.RUNS:
                times, recorded, current, speed, switches = reference.Actuator(p).series(command)
                scenario_path = os.path.join(tmp, "scenario.ron")
                with open(scenario_path, "w") as f:
                    f.write(scenario(times, recorded))
                result = simulate(args.binary, model_path, scenario_path)
                t, v, i = columns(result)
                assert len(t) == len(times) and np.allclose(t, times)
                d_v = np.max(np.abs(1e3 * v - 1e3 * speed))
                d_i = np.max(np.abs(1e3 * i - 1e3 * current))
                worst_v, worst_i = max(worst_v, d_v), max(worst_i, d_i)
                print(f"{label:24s} {run:11s} max |bondgraph - reference|: v {d_v:.2e} mm/s, i {d_i:.2e} mA")
                print("    reference switches: " + ", ".join(f"{a:.6f} s {b}->{c}" for a, b, c in switches))
                print("    bondgraph events:   " + ", ".join(events(result)))
    print(f"largest difference: v {worst_v:.2e} mm/s (tolerance {SPEED_TOLERANCE:g}), "
          f"i {worst_i:.2e} mA (tolerance {CURRENT_TOLERANCE:g})")
    sys.exit(0 if worst_v <= SPEED_TOLERANCE and worst_i <= CURRENT_TOLERANCE else 1)


if __name__ == "__main__":
    main()
