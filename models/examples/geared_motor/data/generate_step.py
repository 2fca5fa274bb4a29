"""A synthetic time series of the geared motor, from known parameter values.

Written independently of the Rust code: the motor's two equations integrated by classical
Runge-Kutta (step 1e-5 s) with the friction's switches located by bisection,

    L_a di/dt = V - R_a i - K N w
    J dw/dt   = N K i - b w - T_f - tau

where T_f = T_C sign(w) while the shaft turns; at rest (w = 0, stuck) the shaft stays put
while |N K i| <= T_S and breaks away when the drive passes T_S; a turning shaft that comes
to rest sticks if |N K i - tau| <= T_S and turns the other way otherwise.

The armature voltage and the brake torque are what a data logger recorded every 10 ms:
between samples each is the straight line through them (the way the fit reads a measured
input), so this script drives the motor with exactly those piecewise-linear signals. The
brake is what lets a run tell the torque constant from the viscous friction: speeds at
several voltages give only (N K/R_a)/(b + beta) and T_C/(b + beta), beta = N^2 K^2/R_a;
a known brake torque gives 1/(b + beta) itself. The truth: K = 0.05 N m/A,
b = 0.05 N m s/rad, T_C = 0.15 N m, T_S = 0.3 N m, with the model file's R_a = 2 ohm,
L_a = 3 mH, N = 20, J = 0.01 kg m^2.

Writes step_exact.csv (no noise: a calibration must recover the truth) and step.csv (Gaussian
noise of 0.05 rad/s on the speed, Python's random.Random(7)).

Run from the repository root: python3 models/examples/geared_motor/data/generate_step.py
"""

import os
import random

R_a, L_a, N, J = 2.0, 0.003, 20.0, 0.01
K, b, T_C, T_S = 0.05, 0.05, 0.15, 0.3
SIGMA = 0.05
SAMPLE = 0.01
END = 2.0
H = 1e-5

# The commanded voltage, recorded every 10 ms: off, 6 V, 12 V, off (the shaft stops and
# sticks), 9 V; and the brake: 1 N m from 0.7 s to 1 s, 0.5 N m from 1.8 s.
def braking(t):
    if 0.7 <= t < 1.0:
        return 1.0
    if t >= 1.8:
        return 0.5
    return 0.0


def commanded(t):
    if t < 0.05:
        return 0.0
    if t < 0.5:
        return 6.0
    if t < 1.0:
        return 12.0
    if t < 1.5:
        return 0.0
    return 9.0


samples = [round(k * SAMPLE, 10) for k in range(int(round(END / SAMPLE)) + 1)]
recorded = [commanded(t) for t in samples]
brake = [braking(t) for t in samples]


def between(values, t):
    k = min(int(t / SAMPLE), len(samples) - 2)
    t0, t1 = samples[k], samples[k + 1]
    return values[k] + (values[k + 1] - values[k]) * (t - t0) / (t1 - t0)


def voltage(t):
    return between(recorded, t)


def rates(t, i, w, mode):
    di = (voltage(t) - R_a * i - K * N * w) / L_a
    if mode == "stuck":
        return di, 0.0
    friction = T_C if mode == "slip+" else -T_C
    return di, (N * K * i - b * w - friction - between(brake, t)) / J


def rk4(t, i, w, mode, h):
    a = rates(t, i, w, mode)
    c = rates(t + h / 2, i + h / 2 * a[0], w + h / 2 * a[1], mode)
    d = rates(t + h / 2, i + h / 2 * c[0], w + h / 2 * c[1], mode)
    e = rates(t + h, i + h * d[0], w + h * d[1], mode)
    return (
        i + h / 6 * (a[0] + 2 * c[0] + 2 * d[0] + e[0]),
        w + h / 6 * (a[1] + 2 * c[1] + 2 * d[1] + e[1]),
    )


def guard(t, i, w, mode):
    """Positive once the mode must end."""
    if mode == "stuck":
        return abs(N * K * i - between(brake, t)) - T_S
    return -w if mode == "slip+" else w


def next_mode(t, i, mode):
    drive = N * K * i - between(brake, t)
    if mode == "stuck":
        return "slip+" if drive > 0 else "slip-"
    if abs(drive) <= T_S:
        return "stuck"
    return "slip-" if mode == "slip+" else "slip+"


def step(t, i, w, mode, h):
    """Advances by h, stopping at a switch: returns (t, i, w, mode)."""
    i1, w1 = rk4(t, i, w, mode, h)
    if guard(t + h, i1, w1, mode) <= 0:
        return t + h, i1, w1, mode
    lo, hi = 0.0, h
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        im, wm = rk4(t, i, w, mode, mid)
        if guard(t + mid, im, wm, mode) > 0:
            hi = mid
        else:
            lo = mid
    i1, w1 = rk4(t, i, w, mode, hi)
    new = next_mode(t + hi, i1, mode)
    if new == "stuck":
        w1 = 0.0
    return t + hi, i1, w1, new


t, i, w, mode = 0.0, 0.0, 0.0, "stuck"
speeds = []
events = []
for target in samples:
    while t < target - 1e-15:
        before = mode
        t, i, w, mode = step(t, i, w, mode, min(H, target - t))
        if mode != before:
            events.append((t, before, mode))
    speeds.append(w)

rng = random.Random(7)
here = os.path.dirname(os.path.abspath(__file__))
for name, noisy in [("step_exact.csv", False), ("step.csv", True)]:
    lines = ["t_s,V_V,tau_mNm,w_rad_s"]
    for t, v, tau, w in zip(samples, recorded, brake, speeds):
        value = w + rng.gauss(0.0, SIGMA) if noisy and w != 0.0 else w
        lines.append(f"{t:.2f},{v:g},{1000 * tau:g},{value:.6f}")
    with open(os.path.join(here, name), "w") as f:
        f.write("\n".join(lines) + "\n")
for e in events:
    print("event at t = %.6f s: %s -> %s" % e)
