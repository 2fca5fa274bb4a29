#!/usr/bin/env python3
"""Reference final states of random linear mechanical networks, for `tests/oracle.rs`.

Each network is masses joined to one another and to the ground by linear springs and
dampers, pushed by constant or ramped forces, started from a given state. This script writes
the equations from Newton's laws itself (it shares nothing with the Rust code):

    dp_i/dt = F_i(t) - sum over elements at i of (force on i),   v_i = p_i / m_i
    dq_s/dt = v_from - v_to                                      (the ground's v is 0)

with a spring's force k q and a damper's b (v_from - v_to), pulling `from` back and `to` on.
The state at the end, x(T), is the exponential of the augmented matrix
[[A, B u1, B u0 + 0], [0, 0, 1], [0, 0, 0]] times T applied to (x0, 0, 1), in mpmath at
`dps` decimal digits, and checked against the same at `dps + 40` digits (the script stops if
the two disagree by more than 1e-30 of the quantity plus its sensitivity S, below).

For each reported quantity (every mass's velocity, every spring's force, the stored energy)
the fixture also gives its sensitivity S = sum over data d of |d * dy/dd|: the data are every
mass, stiffness, damping, force, slope, initial state and the duration. A double-precision
solver that is backward stable componentwise (it solves a problem whose data differ from the
given by a few rounding units) is off by about eps * S; the Rust test allows a stated
multiple of that. S also exposes what no double-precision method can resolve: the phase of a
7e150 rad/s oscillation after one second has S of order 1e150.

It gives as well the sensitivity S_A to each number the solver is handed, perturbed on its
own: the entries of the matrix and of its input columns, the initial state, the output
coefficients and the duration (`entry_sensitivity`). Perturbed apart, these break relations
the data keep (two parallel springs' equal rows, a damper's rows of opposite sign), which
every method that factorizes the matrix in floating point does, and S_A can exceed S a
million times.

Run from the repository root:
    python3 bondgraph-solver/tests/reference/expm_oracle.py > bondgraph-solver/tests/reference/oracle.json
(needs mpmath; about ten minutes).
"""

import json
import random
import sys

import mpmath as mp

SEEDS = list(range(24))


def random_network(seed):
    rng = random.Random(seed)
    masses = [10 ** rng.uniform(-12, 6) for _ in range(rng.randint(1, 4))]
    n = len(masses)
    nodes = list(range(n)) + [None]  # None: the ground
    def element(a, b):
        kind = rng.choice(["spring", "spring", "damper"])
        value = 10 ** rng.uniform(-2, 8) if kind == "spring" else 10 ** rng.uniform(-3, 4)
        return {"kind": kind, "from": a, "to": b, "value": value}

    # One piece (a model file holds one): each mass joined to an earlier one, then more.
    elements = [element(i, rng.randrange(i)) for i in range(1, n)]
    for _ in range(rng.randint(1, n + 1)):
        a = rng.randrange(n)
        elements.append(element(a, rng.choice([x for x in nodes if x != a])))
    forces = []
    for i in range(n):
        if rng.random() < 0.6:
            ramp = rng.random() < 0.3
            forces.append(
                {
                    "mass": i,
                    "initial": rng.uniform(-10, 10),
                    "slope": rng.uniform(-10, 10) if ramp else 0.0,
                }
            )
    # A mass with neither element nor force would be a junction with one bond: push it.
    for i in range(n):
        touched = any(e["from"] == i or e["to"] == i for e in elements)
        if not touched and not any(f["mass"] == i for f in forces):
            forces.append({"mass": i, "initial": rng.uniform(-10, 10), "slope": 0.0})
    momenta = [rng.uniform(-1, 1) * m * 10 ** rng.uniform(-3, 0) for m in masses]
    stretches = [
        rng.uniform(-1, 1) * 10 ** rng.uniform(-4, -1) if e["kind"] == "spring" else 0.0
        for e in elements
    ]
    return {
        "name": f"random_{seed}",
        "masses": masses,
        "elements": elements,
        "forces": forces,
        "momenta": momenta,
        "stretches": stretches,
        "duration": 10 ** rng.uniform(-3, 1),
    }


def two_masses(m1):
    """models/examples/two_masses.ron with a light first mass, pushed by 1 N for 1 s."""
    return {
        "name": f"two_masses_m1_{m1:g}",
        "masses": [m1, 3.0],
        "elements": [
            {"kind": "spring", "from": 0, "to": 1, "value": 50.0},
            {"kind": "damper", "from": 1, "to": None, "value": 2.5},
        ],
        "forces": [{"mass": 0, "initial": 1.0, "slope": 0.0}],
        "momenta": [0.0, 0.0],
        "stretches": [0.0, 0.0],
        "duration": 1.0,
    }


def parallel_springs():
    """Two free masses, 2.5e6 and 2.5e-3 kg, joined by two springs side by side."""
    return {
        "name": "parallel_springs",
        "masses": [2.5e6, 2.5e-3],
        "elements": [
            {"kind": "spring", "from": 0, "to": 1, "value": 1.0e3},
            {"kind": "spring", "from": 0, "to": 1, "value": 3.0e3},
        ],
        "forces": [{"mass": 0, "initial": 1.0, "slope": 0.0}],
        "momenta": [0.0, 0.0],
        "stretches": [0.0, 0.0],
        "duration": 1.0,
    }


def stiff_tip():
    """The flagship's stiffness: a 5e-15 kg tip beside a 1250 N s/m damper, on a spring to 1 kg."""
    return {
        "name": "stiff_tip",
        "masses": [5e-15, 1.0],
        "elements": [
            {"kind": "damper", "from": 0, "to": None, "value": 1250.0},
            {"kind": "spring", "from": 0, "to": 1, "value": 5e5},
        ],
        "forces": [{"mass": 0, "initial": 2.875, "slope": 0.0}, {"mass": 1, "initial": 0.0, "slope": 3.0}],
        "momenta": [0.0, 0.3],
        "stretches": [0.0, -1e-4],
        "duration": 0.2,
    }


def data(net):
    """The network's data as one flat list of (label, value), in a fixed order."""
    out = [(f"m{i}", v) for i, v in enumerate(net["masses"])]
    out += [(f"e{i}", e["value"]) for i, e in enumerate(net["elements"])]
    out += [(f"f{i}", f["initial"]) for i, f in enumerate(net["forces"])]
    out += [(f"s{i}", f["slope"]) for i, f in enumerate(net["forces"])]
    out += [(f"p{i}", v) for i, v in enumerate(net["momenta"])]
    out += [(f"q{i}", v) for i, v in enumerate(net["stretches"])]
    out += [("T", net["duration"])]
    return out


def assemble(net, values):
    """The numbers a solver is handed, from data values (mpf): the augmented matrix M (state
    matrix and input columns), the initial state, the duration, and the output coefficients
    (1/m for each velocity, k for each spring force; the stored energy is sum p (1/m) p / 2 +
    sum q k q / 2 from the same)."""
    n, ne, nf = len(net["masses"]), len(net["elements"]), len(net["forces"])
    it = iter(values)
    m = [next(it) for _ in range(n)]
    e = [next(it) for _ in range(ne)]
    f0 = [next(it) for _ in range(nf)]
    f1 = [next(it) for _ in range(nf)]
    p0 = [next(it) for _ in range(n)]
    q0 = [next(it) for _ in range(ne)]
    T = next(it)
    springs = [j for j, el in enumerate(net["elements"]) if el["kind"] == "spring"]
    size = n + len(springs)
    # states: p_0..p_{n-1}, then the springs' q in element order; columns size, size+1 carry
    # t and 1.
    M = mp.zeros(size + 2, size + 2)
    for j, el in enumerate(net["elements"]):
        a, b = el["from"], el["to"]
        # rate of stretch, as coefficients on p
        rate = {a: 1 / m[a]}
        if b is not None:
            rate[b] = rate.get(b, 0) - 1 / m[b]
        if el["kind"] == "spring":
            s = n + springs.index(j)
            for node, c in rate.items():
                M[s, node] += c
            M[a, s] -= e[j]
            if b is not None:
                M[b, s] += e[j]
        else:
            for node, c in rate.items():
                M[a, node] -= e[j] * c
                if b is not None:
                    M[b, node] += e[j] * c
    for k, force in enumerate(net["forces"]):
        M[force["mass"], size] += f1[k]
        M[force["mass"], size + 1] += f0[k]
    M[size, size + 1] = 1
    x0 = [*p0, *[q0[j] for j in springs], 0, 1]
    coefficients = [1 / m[i] for i in range(n)] + [e[j] for j in springs]
    return M, x0, T, coefficients


def evaluate(M, x0, T, coefficients):
    """Velocities, spring forces and stored energy at T."""
    size = len(coefficients)
    E = mp.expm(M * T)
    x = [mp.fsum(E[r, c] * x0[c] for c in range(size + 2)) for r in range(size)]
    outputs = [c * v for c, v in zip(coefficients, x)]
    stored = mp.fsum(c * v * v / 2 for c, v in zip(coefficients, x))
    return outputs + [stored]


def quantities(net, values):
    """Velocities, spring forces and stored energy at T, from data values (mpf)."""
    return evaluate(*assemble(net, values))


def entry_sensitivity(net, base, h):
    """The sensitivity to each number the solver is handed, perturbed on its own: every
    nonzero entry of M but the clock's, of the initial state and of the output coefficients,
    and the duration. Unlike the data's, such perturbations break the network's exact
    relations (two parallel springs' equal rows, a damper's rows of opposite sign), and any
    method that factorizes the matrix in floating point makes them."""
    M, x0, T, coefficients = assemble(net, base)
    size = len(coefficients)
    values = evaluate(M, x0, T, coefficients)
    total = [mp.mpf(0)] * len(values)

    def add(plus, minus):
        for i in range(len(values)):
            total[i] += abs((plus[i] - minus[i]) / (2 * h))

    for r in range(size + 2):
        for c in range(size + 2):
            if M[r, c] == 0 or (r, c) == (size, size + 1):
                continue
            up, down = M.copy(), M.copy()
            up[r, c] *= 1 + h
            down[r, c] *= 1 - h
            add(evaluate(up, x0, T, coefficients), evaluate(down, x0, T, coefficients))
    for k in range(size):
        if x0[k] == 0:
            continue
        up, down = list(x0), list(x0)
        up[k] *= 1 + h
        down[k] *= 1 - h
        add(evaluate(M, up, T, coefficients), evaluate(M, down, T, coefficients))
    for k in range(size):
        up, down = list(coefficients), list(coefficients)
        up[k] *= 1 + h
        down[k] *= 1 - h
        add(evaluate(M, x0, T, up), evaluate(M, x0, T, down))
    add(evaluate(M, x0, T * (1 + h), coefficients), evaluate(M, x0, T * (1 - h), coefficients))
    return total


def reference(net):
    labels_values = data(net)
    base = [mp.mpf(v) for _, v in labels_values]
    # Digits: enough for the squarings of the exponential and for the phase of the fastest
    # oscillation over T (log10 of the largest rate times T, twice).
    fastest = max(
        [1.0]
        + [e["value"] / m for e in net["elements"] for m in net["masses"]]
        + [(e["value"] / m) ** 0.5 for e in net["elements"] for m in net["masses"]]
    )
    span = max(0, int(mp.log10(fastest * net["duration"])) + 1)
    dps = 60 + 2 * span
    mp.mp.dps = dps + 40
    check = quantities(net, base)
    mp.mp.dps = dps
    values = quantities(net, base)
    # Sensitivities by central differences, h far below any phase error and far above the
    # working precision.
    h = mp.mpf(10) ** -(dps // 2)
    sensitivity = [mp.mpf(0)] * len(values)
    for k, v in enumerate(base):
        if v == 0:
            continue
        up = list(base)
        down = list(base)
        up[k] = v * (1 + h)
        down[k] = v * (1 - h)
        plus = quantities(net, up)
        minus = quantities(net, down)
        for i in range(len(values)):
            sensitivity[i] += abs((plus[i] - minus[i]) / (2 * h))
    for a, b, s in zip(values, check, sensitivity):
        if abs(a - b) > mp.mpf(10) ** -30 * (abs(b) + s):
            sys.exit(f"{net['name']}: {a} and {b} disagree at {dps} digits")
    return values, sensitivity, entry_sensitivity(net, base, h)


def main():
    networks = [random_network(s) for s in SEEDS]
    networks += [two_masses(m1) for m1 in [1e-80, 1e-100, 1e-140, 1e-200, 1e-300]]
    networks += [parallel_springs(), stiff_tip()]
    cases = []
    for net in networks:
        values, sensitivity, entries = reference(net)
        net = dict(net)
        net["expected"] = [float(v) for v in values]
        net["sensitivity"] = [float(s) for s in sensitivity]
        net["entry_sensitivity"] = [float(s) for s in entries]
        cases.append(net)
        print(net["name"], file=sys.stderr)
    json.dump({"generator": "expm_oracle.py", "cases": cases}, sys.stdout, indent=1)
    print()


if __name__ == "__main__":
    main()
