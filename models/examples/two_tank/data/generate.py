"""Synthetic measurements of the two-tank rig, from known parameter values.

Written independently of the Rust code, from the physics (see ../two_tank.ron for the
picture). States: the levels h_1, h_2 (m) and the pipe's volume flow Q (m^3/s):

    A_1 dh_1/dt        = Q_del - Q - G_l p_1                    (tank 1)
    rho L_p/A_p dQ/dt  = p_1 - p_2 - (R_12 + R_f) Q - K_o Q |Q| (the pipe's liquid)
    A_2 dh_2/dt        = Q - c_d sqrt(p_2) - G_2 p_2            (tank 2)

with p_i = rho g h_i, Q_del = Q_p (1 - s_p p_1) the pump's delivered flow, and the hidden
effects' parameters (G_l, K_o, s_p, R_f, G_2) zero in the base model's truth. Observed: both
levels (mm) and the outlet flow c_d sqrt(p_2) (mL/s, a flowmeter on the outlet).

Steady states are solved for the pipe flow by Brent's method (scipy.optimize.brentq, to
1e-15 relative): the orifice's balance gives p_2 from Q, the pipe's p_1, and tank 1's balance
is the residual. Time series integrate the three equations with scipy's DOP853 (rtol 1e-12, atol 1e-14,
the pipe's flow scaled to 1e-4 m^3/s so that every state is of order 0.1-1; the system is
not stiff at these values), segment by segment between the 1 s samples of the
recorded pump flow, which is the straight line through its samples (as the fit reads a
measured input).

The truth: R_12 = 8e6 Pa s/m^3, c_d = 2.2e-6 m^3/(s Pa^(1/2)), L_p = 2 m, with the model
file's rho = 1000 kg/m^3, g = 9.81 m/s^2, A_1 = A_2 = 0.01 m^2, A_p = 7.854e-5 m^2. Hidden
effects (one at a time), with the value of the committed data sets and the range a seeded
variant draws from:

    tank-1-leak          G_l = 2.0e-9 m^3/(s Pa)     (1.0e-9 .. 3.0e-9)
    turbulent-pipe-loss  K_o = 1.2e10 Pa s^2/m^6     (0.6e10 .. 2.0e10)
    pump-pressure-sag    s_p = 1.0e-5 1/Pa           (0.6e-5 .. 1.5e-5)
    pipe-fouling         R_f = 4.0e6 Pa s/m^3        (2.0e6 .. 6.0e6)   a refit of R_12
    tank-2-leak          G_2 = 2.0e-9 m^3/(s Pa)     (1.0e-9 .. 3.0e-9) (the library's decoy;
                                                      data with it hidden are for checks only)

Noise: Gaussian, 2 mm on each level and 1 mL/s on the outlet flow (about 1 % of their
ranges), from numpy's default_rng(seed).

Usage (from anywhere):
    python3 generate.py                       # the committed files in this folder
    python3 generate.py --seed 7 --hidden tank-1-leak --out /tmp/d   # one seeded variant
    python3 generate.py --seed 7 --hidden none --out /tmp/d          # nothing hidden
A seeded variant draws the hidden value uniformly from its range (first draw of the seed's
generator), then the noise; it writes steady.csv, step_1.csv, step_2.csv and truth.json.
"""

import argparse
import json
import os

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

HERE = os.path.dirname(os.path.abspath(__file__))

RHO, G = 1000.0, 9.81
A_1, A_2, A_P = 0.01, 0.01, 7.854e-5
TRUTH = {"R_12": 8.0e6, "c_d": 2.2e-6, "L_p": 2.0}
NO_EFFECT = {"G_l": 0.0, "K_o": 0.0, "s_p": 0.0, "R_f": 0.0, "G_2": 0.0}
HIDDEN = {
    "tank-1-leak": ("G_l", 2.0e-9, (1.0e-9, 3.0e-9)),
    "turbulent-pipe-loss": ("K_o", 1.2e10, (0.6e10, 2.0e10)),
    "pump-pressure-sag": ("s_p", 1.0e-5, (0.6e-5, 1.5e-5)),
    "pipe-fouling": ("R_f", 4.0e6, (2.0e6, 6.0e6)),
    "tank-2-leak": ("G_2", 2.0e-9, (1.0e-9, 3.0e-9)),
}
# The real causes: one committed data set each (the refit in disguise and the decoy too, for
# the checks that they are reported as such).
COMMITTED = ["tank-1-leak", "turbulent-pipe-loss", "pump-pressure-sag", "pipe-fouling"]
SIGMA_LEVEL_MM, SIGMA_FLOW_ML_S = 2.0, 1.0

# The steady sweep: pump flows in mL/s.
STEADY_FLOWS = [20.0 + 5.0 * k for k in range(27)]  # 20 .. 150 mL/s
SAMPLE, DURATION = 1.0, 600.0
H0 = 0.1  # both runs start with both levels at 100 mm and the pipe at rest


def run_1(t):
    """The pump's commanded flow in run 1, mL/s: a staircase."""
    if t < 120.0:
        return 60.0
    if t < 300.0:
        return 130.0
    if t < 450.0:
        return 40.0
    return 90.0


def run_2(t):
    """Run 2: a ramp from 40 to 150 mL/s over 300 s, held, then a drop to 50 mL/s."""
    if t < 300.0:
        return 40.0 + 110.0 * t / 300.0
    if t < 420.0:
        return 150.0
    return 50.0


RUNS = [("step_1.csv", run_1), ("step_2.csv", run_2)]


def parameters(hidden=None, value=None):
    p = dict(TRUTH)
    p.update(NO_EFFECT)
    if hidden is not None:
        p[HIDDEN[hidden][0]] = value
    return p


def orifice(p, p_2):
    return p["c_d"] * np.sign(p_2) * np.sqrt(abs(p_2))


def steady(p, q_p):
    """Steady levels (m) and outlet flow (m^3/s) at pump flow q_p (m^3/s)."""

    def tank_2_pressure(q):
        # q = c_d sqrt(p_2) + G_2 p_2: a quadratic in s = sqrt(p_2)
        if p["G_2"] == 0.0:
            return (q / p["c_d"]) ** 2
        a, b = p["G_2"], p["c_d"]
        s = (-b + np.sqrt(b * b + 4.0 * a * q)) / (2.0 * a)
        return s * s

    def tank_1_pressure(q):
        return tank_2_pressure(q) + (p["R_12"] + p["R_f"]) * q + p["K_o"] * q * abs(q)

    def balance(q):
        p_1 = tank_1_pressure(q)
        return q_p * (1.0 - p["s_p"] * p_1) - p["G_l"] * p_1 - q

    q = brentq(balance, 0.0, q_p, xtol=1e-22, rtol=1e-15, maxiter=500)
    p_1, p_2 = tank_1_pressure(q), tank_2_pressure(q)
    return p_1 / (RHO * G), p_2 / (RHO * G), orifice(p, p_2)


# The pipe's flow is integrated in units of Q_SCALE so that every state is of order 0.1-1.
Q_SCALE = 1e-4


def rates(p, q_p):
    inertance = RHO * p["L_p"] / A_P

    def f(t, x):
        h_1, h_2, q = x[0], x[1], x[2] * Q_SCALE
        p_1, p_2 = RHO * G * h_1, RHO * G * h_2
        delivered = q_p(t) * (1.0 - p["s_p"] * p_1)
        return [
            (delivered - q - p["G_l"] * p_1) / A_1,
            (q - orifice(p, p_2) - p["G_2"] * p_2) / A_2,
            (p_1 - p_2 - (p["R_12"] + p["R_f"]) * q - p["K_o"] * q * abs(q)) / inertance / Q_SCALE,
        ]

    return f


def series(p, command):
    """One run: sample times (s), the recorded pump flow (mL/s), levels (m), outlet (m^3/s)."""
    times = np.arange(0.0, DURATION + SAMPLE / 2, SAMPLE)
    recorded = np.array([command(t) for t in times])
    x = np.array([H0, H0, 0.0])
    states = [x.copy()]
    for k in range(len(times) - 1):
        t0, t1 = times[k], times[k + 1]
        u0, u1 = recorded[k] * 1e-6, recorded[k + 1] * 1e-6

        def q_p(t, t0=t0, t1=t1, u0=u0, u1=u1):
            return u0 + (u1 - u0) * (t - t0) / (t1 - t0)

        sol = solve_ivp(rates(p, q_p), (t0, t1), x, method="DOP853", rtol=1e-12, atol=1e-14)
        if not sol.success:
            raise RuntimeError(sol.message)
        x = sol.y[:, -1]
        states.append(x.copy())
    states = np.array(states)
    outlet = np.array([orifice(p, RHO * G * h) for h in states[:, 1]])
    states[:, 2] *= Q_SCALE
    return times, recorded, states[:, 0], states[:, 1], outlet


def write(path, header, rows):
    with open(path, "w") as f:
        f.write(",".join(header) + "\n")
        for row in rows:
            f.write(",".join(row) + "\n")


def steady_rows(p, rng):
    rows = []
    for q_mL in STEADY_FLOWS:
        h_1, h_2, out = steady(p, q_mL * 1e-6)
        noise = (0.0, 0.0, 0.0) if rng is None else (
            SIGMA_LEVEL_MM * rng.standard_normal(),
            SIGMA_LEVEL_MM * rng.standard_normal(),
            SIGMA_FLOW_ML_S * rng.standard_normal(),
        )
        rows.append([f"{q_mL:g}", f"{1e3 * h_1 + noise[0]:.4f}", f"{1e3 * h_2 + noise[1]:.4f}",
                     f"{1e6 * out + noise[2]:.4f}"])
    return rows


def series_rows(p, command, rng):
    times, recorded, h_1, h_2, out = series(p, command)
    rows = []
    for k in range(len(times)):
        noise = (0.0, 0.0, 0.0) if rng is None else (
            SIGMA_LEVEL_MM * rng.standard_normal(),
            SIGMA_LEVEL_MM * rng.standard_normal(),
            SIGMA_FLOW_ML_S * rng.standard_normal(),
        )
        rows.append([f"{times[k]:g}", f"{recorded[k]:g}", f"{1e3 * h_1[k] + noise[0]:.4f}",
                     f"{1e3 * h_2[k] + noise[1]:.4f}", f"{1e6 * out[k] + noise[2]:.4f}"])
    return rows


STEADY_HEADER = ["Q_p_mL_s", "h_1_mm", "h_2_mm", "Q_out_mL_s"]
SERIES_HEADER = ["t_s", "Q_p_mL_s", "h_1_mm", "h_2_mm", "Q_out_mL_s"]


def data_set(out, p, seed, exact=False):
    """steady.csv, step_1.csv, step_2.csv (and with exact, their noise-free twins)."""
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
        # The committed data: the base truth (seed 1, and exact), one set per hidden effect.
        data_set(HERE, parameters(), 1, exact=True)
        for k, hidden in enumerate(COMMITTED):
            name, value, _ = HIDDEN[hidden]
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
