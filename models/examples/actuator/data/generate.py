"""Synthetic measurements of the lead-screw actuator, from known parameter values.

Written independently of the Rust code, from the physics (see ../actuator.ron for the
picture). With N = 1/n_s (radians per metre of travel), the rotor merged into the carriage
(M = m + J_m N^2) and the motor constant K_e(i) = K (1 - a_r |i|), the states are the
armature current i (A) and the carriage's velocity v (m/s):

    L_a di/dt = V - R_a i - U_b tanh(i/i_b) - K_e(i) N v
    M dv/dt   = K_e(i) N i - F_L - (b + b_s) v - F_f          (while the carriage slides)
    dv/dt     = 0, v = 0                                      (while the guide holds it)

F_f is the guide's friction: +-F_C' sliding, with F_C' = F_C + mu_L F_L (and F_S' likewise);
with a Stribeck velocity v_s, below v_s it is +-(F_S' - (F_S' - F_C')|v|/v_s) (the modes
creep+ and creep-: the piecewise-linear law of the library's Stribeck contact). The guide
holds while |K_e N i - F_L| <= F_S' and breaks away when that force passes F_S'; a sliding
carriage that comes to rest sticks if the guide can then hold it and turns back otherwise.
The switches are located as events (scipy's solve_ivp with DOP853, rtol 1e-12, atol 1e-12,
its event root-finding on the dense output) and the integration restarts in the new mode.
Inputs are the recorded voltage and load force, straight lines between their 1 ms samples
(as the fit reads a measured input); each sample interval is integrated on its own.

Steady states are found in closed form up to scalar roots (scipy.optimize.brentq to 1e-15):
stalled when the stall current's force lies within +-F_S', else the velocity where the net
force, a decreasing function of v, is zero.

The truth: K = 0.03 N m/A, b = 40 N s/m, F_C = 10 N, F_S = 15 N, J_m = 1.5e-5 kg m^2, with
the model file's R_a = 1.2 ohm, L_a = 0.4 mH, n_s = 7.957747e-4 m (5 mm lead), m = 2 kg.
Hidden effects, one at a time (the value of the committed data sets; the range a seeded
variant draws from):

    stribeck-weakening        v_s  = 8 mm/s            (5 .. 12 mm/s)
    brush-voltage-drop        U_b  = 0.25 V            (0.15 .. 0.5 V), i_b = 0.05 A fixed
    load-dependent-friction   mu_L = 0.08              (0.04 .. 0.15)
    guide-seal-drag           b_s  = 20 N s/m          (10 .. 40 N s/m)   a refit of b
    field-weakening           a_r  = 0.02 1/A          (0.01 .. 0.04)     the decoy

Noise: Gaussian, 1 mm/s on the carriage's speed (none while it is stalled: an encoder counts
nothing) and 10 mA on the current, from numpy's default_rng(seed).

Usage:
    python3 generate.py                                           # the committed files
    python3 generate.py --seed 7 --hidden brush-voltage-drop --out /tmp/d   # one variant
    python3 generate.py --seed 7 --hidden none --out /tmp/d                # nothing hidden
"""

import argparse
import json
import os

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

HERE = os.path.dirname(os.path.abspath(__file__))

R_A, L_A, N_S, MASS, I_B = 1.2, 4.0e-4, 7.957747e-4, 2.0, 0.05
TRUTH = {"K": 0.03, "b": 40.0, "F_C": 10.0, "F_S": 15.0, "J_m": 1.5e-5}
NO_EFFECT = {"v_s": 0.0, "U_b": 0.0, "mu_L": 0.0, "b_s": 0.0, "a_r": 0.0}
HIDDEN = {
    "stribeck-weakening": ("v_s", 8.0e-3, (5.0e-3, 12.0e-3)),
    "brush-voltage-drop": ("U_b", 0.25, (0.15, 0.5)),
    "load-dependent-friction": ("mu_L", 0.08, (0.04, 0.15)),
    "guide-seal-drag": ("b_s", 20.0, (10.0, 40.0)),
    "field-weakening": ("a_r", 0.02, (0.01, 0.04)),
}
COMMITTED = ["stribeck-weakening", "brush-voltage-drop", "load-dependent-friction", "guide-seal-drag"]
SIGMA_SPEED_MM_S, SIGMA_CURRENT_MA = 1.0, 10.0

STEADY_ROWS = (
    [(v, 0.0) for v in [0.3, 0.45, 0.5, 0.55, 0.6, 0.7, 0.8, 1.0, 1.5, 2.0, 3.0, 4.0, 6.0, 8.0, 10.0, 12.0]]
    + [(v, 20.0) for v in [0.8, 1.2, 1.3, 1.4, 1.6, 2.0, 3.0, 4.0, 6.0, 8.0, 10.0, 12.0]]
    + [(v, 40.0) for v in [1.5, 1.8, 1.9, 2.0, 2.2, 2.5, 3.0, 4.0, 6.0, 8.0, 10.0, 12.0]]
)
SAMPLE, DURATION = 1.0e-3, 0.6


def run_1(t):
    """Voltage (V) and load force (N) of run 1: forward at 6 then 12 V, stop, reverse."""
    if t < 0.01:
        v = 0.0
    elif t < 0.15:
        v = 6.0
    elif t < 0.30:
        v = 12.0
    elif t < 0.40:
        v = 0.0
    elif t < 0.55:
        v = -8.0
    else:
        v = 0.0
    return v, 0.0


def run_2(t):
    """Run 2, against a hanging weight of 25 N: held at 0.8 V, up at 4 then 10 V, held again,
    then eased to 0.3 V, when the weight back-drives the screw slowly (about 5 mm/s, where
    velocity weakening would show)."""
    if t < 0.02:
        v = 0.8
    elif t < 0.15:
        v = 4.0
    elif t < 0.30:
        v = 10.0
    elif t < 0.42:
        v = 0.8
    else:
        v = 0.3
    return v, 25.0


RUNS = [("step_1.csv", run_1), ("step_2.csv", run_2)]


def parameters(hidden=None, value=None):
    p = dict(TRUTH)
    p.update(NO_EFFECT)
    if hidden is not None:
        p[HIDDEN[hidden][0]] = value
    return p


class Actuator:
    def __init__(self, p):
        self.p = p
        self.n = 1.0 / N_S
        self.mass = MASS + p["J_m"] * self.n**2

    def k_e(self, i):
        return self.p["K"] * (1.0 - self.p["a_r"] * abs(i))

    def brush(self, i):
        return self.p["U_b"] * np.tanh(i / I_B)

    def limits(self, f_l):
        """(breakaway, Coulomb) forces of the guide at load f_l."""
        mu = self.p["mu_L"] * f_l
        return self.p["F_S"] + mu, self.p["F_C"] + mu

    def friction(self, mode, v, f_l):
        f_s, f_c = self.limits(f_l)
        sign = 1.0 if mode.endswith("+") else -1.0
        if mode.startswith("creep"):
            return sign * (f_s - (f_s - f_c) * abs(v) / self.p["v_s"])
        return sign * f_c

    def drive(self, i, f_l):
        """Force on the carriage from the screw, less the load."""
        return self.k_e(i) * self.n * i - f_l

    def rates(self, mode, voltage, load):
        p = self.p

        def f(t, x):
            i, v = x
            di = (voltage(t) - R_A * i - self.brush(i) - self.k_e(i) * self.n * v) / L_A
            if mode == "stuck":
                return [di, 0.0]
            f_l = load(t)
            dv = (self.drive(i, f_l) - (p["b"] + p["b_s"]) * v - self.friction(mode, v, f_l)) / self.mass
            return [di, dv]

        return f

    def events(self, mode, load):
        """The guards of mode, each a function crossing zero upward where the mode ends, with
        the mode it leads to (None: decided by whether the guide can hold)."""
        stribeck = self.p["v_s"] > 0.0
        fast = "slip"
        slow = "creep" if stribeck else "slip"
        if mode == "stuck":
            return [
                (lambda t, x: self.drive(x[0], load(t)) - self.limits(load(t))[0], slow + "+"),
                (lambda t, x: -self.drive(x[0], load(t)) - self.limits(load(t))[0], slow + "-"),
            ]
        sign = 1.0 if mode.endswith("+") else -1.0
        guards = []
        if mode.startswith("slip") and stribeck:
            guards.append((lambda t, x: self.p["v_s"] - sign * x[1], "creep" + mode[-1]))
        else:
            guards.append((lambda t, x: -sign * x[1], None))  # comes to rest
        if mode.startswith("creep"):
            guards.append((lambda t, x: sign * x[1] - self.p["v_s"], "slip" + mode[-1]))
        return guards

    def after_rest(self, t, i, mode, load):
        """The mode after a sliding carriage comes to rest at time t."""
        f_s, _ = self.limits(load(t))
        h = self.drive(i, load(t))
        if abs(h) <= f_s:
            return "stuck"
        stribeck = self.p["v_s"] > 0.0
        return ("creep" if stribeck else "slip") + ("+" if h > 0 else "-")

    def segment(self, t0, t1, x, mode, voltage, load, switches):
        """Integrates from t0 to t1, switching modes at events; returns (x, mode)."""
        t = t0
        for _ in range(100):
            if mode == "stuck":
                # A guide that cannot hold at the start (a load heavier than the breakaway
                # force before the current has built up) lets go at once: solve_ivp's events
                # see only crossings, so this is checked here.
                h, f_s = self.drive(x[0], load(t)), self.limits(load(t))[0]
                if abs(h) > f_s:
                    new = ("creep" if self.p["v_s"] > 0.0 else "slip") + ("+" if h > 0 else "-")
                    switches.append((t, mode, new))
                    mode = new
            guards = self.events(mode, load)
            funcs = []
            for g, _ in guards:
                def event(tt, xx, g=g):
                    return g(tt, xx)
                event.terminal = True
                event.direction = 1.0
                funcs.append(event)
            sol = solve_ivp(self.rates(mode, voltage, load), (t, t1), x, method="DOP853",
                            rtol=1e-12, atol=1e-12, events=funcs)
            if not sol.success:
                raise RuntimeError(sol.message)
            fired = [k for k, te in enumerate(sol.t_events) if len(te) > 0]
            if not fired:
                return sol.y[:, -1], mode
            k = min(fired, key=lambda k: sol.t_events[k][0])
            t = sol.t_events[k][0]
            x = sol.y_events[k][0].copy()
            new = guards[k][1]
            if new is None:
                x[1] = 0.0
                new = self.after_rest(t, x[0], mode, load)
            switches.append((t, mode, new))
            mode = new
            if t >= t1:
                return x, mode
        raise RuntimeError(f"more than 100 switches between {t0} and {t1} s")

    def series(self, command):
        times = np.round(np.arange(0.0, DURATION + SAMPLE / 2, SAMPLE), 10)
        recorded = np.array([command(t) for t in times])
        x = np.array([0.0, 0.0])
        mode = "stuck"
        states, switches = [x.copy()], []
        for k in range(len(times) - 1):
            t0, t1 = times[k], times[k + 1]
            (v0, f0), (v1, f1) = recorded[k], recorded[k + 1]

            def voltage(t, t0=t0, t1=t1, v0=v0, v1=v1):
                return v0 + (v1 - v0) * (t - t0) / (t1 - t0)

            def load(t, t0=t0, t1=t1, f0=f0, f1=f1):
                return f0 + (f1 - f0) * (t - t0) / (t1 - t0)

            x, mode = self.segment(t0, t1, x, mode, voltage, load, switches)
            states.append(x.copy())
        states = np.array(states)
        return times, recorded, states[:, 0], states[:, 1], switches

    def current(self, voltage, v):
        """The steady current at carriage speed v."""
        def residual(i):
            return R_A * i + self.brush(i) + self.k_e(i) * self.n * v - voltage
        bound = 2.0 * (abs(voltage) + self.p["K"] * self.n * abs(v)) / R_A + 1.0
        return brentq(residual, -bound, bound, xtol=1e-15, rtol=1e-15, maxiter=500)

    def steady(self, voltage, f_l):
        """(current A, speed m/s, regime) at steady state from rest."""
        f_s, _ = self.limits(f_l)
        i0 = self.current(voltage, 0.0)
        h = self.drive(i0, f_l)
        if abs(h) <= f_s:
            return i0, 0.0, "stalled"
        if h < 0:
            raise ValueError(f"V = {voltage}, F_L = {f_l}: back-driven, not in the design")
        def net(v):
            mode = "creep+" if v < self.p["v_s"] else "slip+"
            return self.drive(self.current(voltage, v), f_l) - (self.p["b"] + self.p["b_s"]) * v \
                - self.friction(mode, v, f_l)

        # At v_max the back-EMF alone matches the voltage: no current, so the net force is
        # negative; it is positive at rest (the carriage broke away), and decreasing between.
        v_max = voltage / (self.p["K"] * self.n)
        v = brentq(net, 0.0, v_max, xtol=1e-16, rtol=1e-15, maxiter=500)
        regime = "creeping" if self.p["v_s"] > 0.0 and v < self.p["v_s"] else "sliding"
        return self.current(voltage, v), v, regime


def write(path, header, rows):
    with open(path, "w") as f:
        f.write(",".join(header) + "\n")
        for row in rows:
            f.write(",".join(row) + "\n")


STEADY_HEADER = ["V_V", "F_L_N", "v_mm_s", "i_mA"]
SERIES_HEADER = ["t_s", "V_V", "F_L_N", "v_mm_s", "i_mA"]


def noisy(rng, speed_mm_s, current_ma):
    if rng is None:
        return speed_mm_s, current_ma
    e_v, e_i = rng.standard_normal(), rng.standard_normal()
    speed = speed_mm_s + SIGMA_SPEED_MM_S * e_v if speed_mm_s != 0.0 else 0.0
    return speed, current_ma + SIGMA_CURRENT_MA * e_i


def steady_rows(p, rng):
    model, rows = Actuator(p), []
    for voltage, f_l in STEADY_ROWS:
        i, v, _ = model.steady(voltage, f_l)
        speed, current = noisy(rng, 1e3 * v, 1e3 * i)
        rows.append([f"{voltage:g}", f"{f_l:g}", f"{speed:.4f}", f"{current:.3f}"])
    return rows


def series_rows(p, command, rng):
    times, recorded, i, v, _ = Actuator(p).series(command)
    rows = []
    for k in range(len(times)):
        speed, current = noisy(rng, 1e3 * v[k], 1e3 * i[k])
        rows.append([f"{times[k]:.3f}", f"{recorded[k][0]:g}", f"{recorded[k][1]:g}",
                     f"{speed:.5f}", f"{current:.4f}"])
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
