"""Synthetic measurements of the two heated blocks, from known parameter values.

Written independently of the Rust code, from the heat balances of the blocks (see
../thermal.lg.ron for the picture), in absolute temperatures T1, T2 (K):

    C_1 dT1/dt = (1 - eta_h) P_1 - (T1 - T2)/(R_12 + R_c) - (T1 - T_amb)/R_1a
                 - eA sigma (T1^4 - T_amb^4) - h_n sign(T1 - T_amb) |T1 - T_amb|^(5/4)
    C_2 dT2/dt = P_2 + (T1 - T2)/(R_12 + R_c) - (T2 - T_amb)/R_2a

with the hidden effects' parameters (eta_h, R_c, eA, h_n) zero in the base model's truth.
Observed: both temperatures (thermocouples, K). The room's temperature T_amb is constant
through each run and each steady row.

Steady states: the linear solution, then scipy.optimize.root (hybr) from it when a
nonlinear effect is hidden, to a heat balance within 1e-10 W. Time series: both blocks at room temperature at t = 0,
integrated by scipy's DOP853 (rtol 1e-12, atol 1e-10 K), segment by segment between the
20 s samples of the recorded heater powers, which are straight lines between their samples
(as the fit reads a measured input).

The truth: C_1 = 450 J/K, C_2 = 900 J/K, R_12 = 0.8 K/W, R_1a = 4 K/W, R_2a = 2.5 K/W
(sigma = 5.670374419e-8 W/(m^2 K^4)). Hidden effects, one at a time (the value of the
committed data sets; the range a seeded variant draws from):

    radiation            eA    = 0.01 m^2      (0.005 .. 0.015 m^2)
    heater-lead-loss     eta_h = 0.08          (0.05 .. 0.15)
    contact-resistance   R_c   = 0.4 K/W       (0.2 .. 0.8 K/W)        a refit of R_12
    natural-convection   h_n   = 0.02 W/K^1.25 (0.01 .. 0.04)          the decoy

Noise: Gaussian, 0.2 K on each temperature, from numpy's default_rng(seed).

Usage:
    python3 generate.py                                        # the committed files
    python3 generate.py --seed 7 --hidden radiation --out /tmp/d   # one seeded variant
    python3 generate.py --seed 7 --hidden none --out /tmp/d        # nothing hidden
"""

import argparse
import json
import os

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import root

HERE = os.path.dirname(os.path.abspath(__file__))

SIGMA_SB = 5.670374419e-8
TRUTH = {"C_1": 450.0, "C_2": 900.0, "R_12": 0.8, "R_1a": 4.0, "R_2a": 2.5}
NO_EFFECT = {"eA": 0.0, "eta_h": 0.0, "R_c": 0.0, "h_n": 0.0}
HIDDEN = {
    "radiation": ("eA", 0.01, (0.005, 0.015)),
    "heater-lead-loss": ("eta_h", 0.08, (0.05, 0.15)),
    "contact-resistance": ("R_c", 0.4, (0.2, 0.8)),
    "natural-convection": ("h_n", 0.02, (0.01, 0.04)),
}
COMMITTED = ["radiation", "heater-lead-loss", "contact-resistance"]
SIGMA_T = 0.2

STEADY_ROWS = [(p_1, p_2, t_amb) for t_amb in (290.0, 300.0, 310.0)
               for p_2 in (0.0, 12.0, 24.0) for p_1 in (0.0, 8.0, 16.0, 24.0)]
SAMPLE, DURATION = 20.0, 10800.0


def run_1(t):
    """Heater powers (W) and room temperature (K) of run 1: heater 1, then heater 2, then both."""
    if t < 3600.0:
        return 20.0, 0.0, 295.0
    if t < 7200.0:
        return 0.0, 20.0, 295.0
    return 10.0, 10.0, 295.0


def run_2(t):
    """Run 2, in a warmer room: heater 1 hard, then mostly heater 2."""
    if t < 5400.0:
        return 24.0, 0.0, 305.0
    return 8.0, 24.0, 305.0


RUNS = [("step_1.csv", run_1), ("step_2.csv", run_2)]


def parameters(hidden=None, value=None):
    p = dict(TRUTH)
    p.update(NO_EFFECT)
    if hidden is not None:
        p[HIDDEN[hidden][0]] = value
    return p


def heat_in(p, t_1, t_2, p_1, p_2, t_amb):
    """The net heat flows into block 1 and block 2 (W)."""
    rise = t_1 - t_amb
    bar = (t_1 - t_2) / (p["R_12"] + p["R_c"])
    q_1 = ((1.0 - p["eta_h"]) * p_1 - bar - rise / p["R_1a"]
           - p["eA"] * SIGMA_SB * (t_1**4 - t_amb**4)
           - p["h_n"] * np.sign(rise) * abs(rise) ** 1.25)
    q_2 = p_2 + bar - (t_2 - t_amb) / p["R_2a"]
    return q_1, q_2


def steady(p, p_1, p_2, t_amb):
    r = p["R_12"] + p["R_c"]
    g = np.array([[1 / r + 1 / p["R_1a"], -1 / r], [-1 / r, 1 / r + 1 / p["R_2a"]]])
    rise = np.linalg.solve(g, [(1.0 - p["eta_h"]) * p_1, p_2])
    x0 = t_amb + rise
    if p["eA"] == 0.0 and p["h_n"] == 0.0:
        return x0
    sol = root(lambda x: heat_in(p, x[0], x[1], p_1, p_2, t_amb), x0, method="hybr",
               options={"xtol": 1e-15})
    # hybr may stop saying no further improvement is possible: that is at the rounding level,
    # which the balance's residual checks.
    if max(abs(q) for q in heat_in(p, *sol.x, p_1, p_2, t_amb)) > 1e-10:
        raise RuntimeError(sol.message)
    return sol.x


def series(p, command):
    times = np.arange(0.0, DURATION + SAMPLE / 2, SAMPLE)
    recorded = np.array([command(t) for t in times])
    x = np.array([recorded[0][2], recorded[0][2]])
    states = [x.copy()]
    for k in range(len(times) - 1):
        t0, t1 = times[k], times[k + 1]
        u0, u1 = recorded[k], recorded[k + 1]

        def f(t, x, t0=t0, t1=t1, u0=u0, u1=u1):
            u = u0 + (u1 - u0) * (t - t0) / (t1 - t0)
            q_1, q_2 = heat_in(p, x[0], x[1], u[0], u[1], u[2])
            return [q_1 / p["C_1"], q_2 / p["C_2"]]

        sol = solve_ivp(f, (t0, t1), x, method="DOP853", rtol=1e-12, atol=1e-10)
        if not sol.success:
            raise RuntimeError(sol.message)
        x = sol.y[:, -1]
        states.append(x.copy())
    states = np.array(states)
    return times, recorded, states[:, 0], states[:, 1]


def write(path, header, rows):
    with open(path, "w") as f:
        f.write(",".join(header) + "\n")
        for row in rows:
            f.write(",".join(row) + "\n")


STEADY_HEADER = ["P_1_W", "P_2_W", "T_amb_K", "T_1_K", "T_2_K"]
SERIES_HEADER = ["t_s", "P_1_W", "P_2_W", "T_amb_K", "T_1_K", "T_2_K"]


def noise(rng):
    return (0.0, 0.0) if rng is None else (SIGMA_T * rng.standard_normal(), SIGMA_T * rng.standard_normal())


def steady_rows(p, rng):
    rows = []
    for p_1, p_2, t_amb in STEADY_ROWS:
        t_1, t_2 = steady(p, p_1, p_2, t_amb)
        e = noise(rng)
        rows.append([f"{p_1:g}", f"{p_2:g}", f"{t_amb:g}", f"{t_1 + e[0]:.4f}", f"{t_2 + e[1]:.4f}"])
    return rows


def series_rows(p, command, rng):
    times, recorded, t_1, t_2 = series(p, command)
    rows = []
    for k in range(len(times)):
        e = noise(rng)
        rows.append([f"{times[k]:g}", f"{recorded[k][0]:g}", f"{recorded[k][1]:g}", f"{recorded[k][2]:g}",
                     f"{t_1[k] + e[0]:.5f}", f"{t_2[k] + e[1]:.5f}"])
    return rows


def data_set(out, p, seed, exact=False):
    os.makedirs(out, exist_ok=True)
    rng = np.random.default_rng(seed)
    write(os.path.join(out, "steady.csv"), STEADY_HEADER, steady_rows(p, rng))
    for name, command in RUNS:
        write(os.path.join(out, name), SERIES_HEADER, series_rows(p, command, rng))
    if exact:
        write(os.path.join(out, "steady_exact.csv"), STEADY_HEADER, steady_rows(p, None))
        for name, command in RUNS:
            write(os.path.join(out, name.replace(".csv", "_exact.csv")), SERIES_HEADER,
                  series_rows(p, command, None))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seed", type=int)
    parser.add_argument("--hidden", choices=sorted(HIDDEN) + ["none"])
    parser.add_argument("--out")
    args = parser.parse_args()
    if args.seed is None:
        data_set(HERE, parameters(), 1, exact=True)
        for k, hidden in enumerate(COMMITTED):
            _, value, _ = HIDDEN[hidden]
            data_set(os.path.join(HERE, "hidden", hidden), parameters(hidden, value), 11 + k)
        print("wrote", HERE)
        return
    if args.hidden is None or args.out is None:
        parser.error("--seed needs --hidden and --out")
    rng = np.random.default_rng(args.seed)
    truth = dict(TRUTH)
    if args.hidden == "none":
        p = parameters()
    else:
        name, _, (low, high) = HIDDEN[args.hidden]
        value = float(low + (high - low) * rng.random())
        p = parameters(args.hidden, value)
        truth[name] = value
    data_set(args.out, p, int(rng.integers(2**31)))
    with open(os.path.join(args.out, "truth.json"), "w") as f:
        json.dump({"seed": args.seed, "hidden": args.hidden, "values": truth}, f, indent=2)
    print("wrote", args.out, json.dumps(truth))


if __name__ == "__main__":
    main()
