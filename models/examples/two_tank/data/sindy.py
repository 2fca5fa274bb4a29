"""A data-driven identifier on the same runs: SINDy (pysindy's STLSQ, smoothed derivatives).

For each data set (the base truth and each hidden effect, runs step_1.csv and step_2.csv
together), the levels' rates dh_1/dt, dh_2/dt (mm/s) are estimated by pysindy's
SmoothedFiniteDifference (Savitzky-Golay, 31 samples, order 3) and regressed by pysindy's
STLSQ (sequentially thresholded least squares; terms scaled to unit RMS, threshold 5 % of the
rate's RMS; the terms smoothed by the same filter) on a library of candidate terms in the
levels h_1, h_2 (mm) and the pump flow u (mL/s):

    1, h_1, h_2, sqrt(h_2), u, u*h_1, sign(d)*sqrt(|d|) with d = h_1 - h_2

The pipe's flow is not measured, so SINDy sees the levels only: the pipe's inertance (the
23 s sloshing) is outside its reach and the pipe's flow appears through d = h_1 - h_2
(laminar: a term in h_1 - h_2; turbulent: in sign(d) sqrt|d|). What each hidden effect
should leave in the equations (with A = 0.01 m^2, a flow of 1 mL/s raises a level by
0.1 mm/s):

    base                 dh_1/dt = 0.1 u - k (h_1 - h_2)     dh_2/dt = k (h_1 - h_2) - c sqrt(h_2)
    tank-1-leak          dh_1/dt gains -G_l rho g/A_1 h_1: the h_1 and h_2 terms no longer cancel
    pump-pressure-sag    dh_1/dt gains a u*h_1 term (-0.1 s_p rho g/1000 per mm)
    turbulent-pipe-loss  the pipe's terms move from (h_1 - h_2) towards sign(d) sqrt|d|
    pipe-fouling         k smaller (a refit, like the physical model's)

A second regression sidesteps the unmeasured pipe flow with the mass balance of both
tanks, which the pipe's flow drops out of: with equal areas, d(h_1 + h_2)/dt (mm/s) on the
library 1, h_1, h_2, u, u*h_1, q (q the measured outlet flow, mL/s). The base truth is
0.1 u - 0.1 q; a leak from tank 1 adds -G_l rho g/A_1 h_1 (-1.96e-3 1/s at the committed
value), the pump's sag -0.1 s_p rho g/1000 u*h_1 (-9.8e-6 per mm per mL/s); the pipe's
effects (turbulence, fouling) leave it unchanged.

Run from the repository root: python3 models/examples/two_tank/data/sindy.py
"""

import csv
import os

import numpy as np
import pysindy as ps
from scipy.signal import savgol_filter

HERE = os.path.dirname(os.path.abspath(__file__))
SETS = [("base", HERE)] + [(d, os.path.join(HERE, "hidden", d))
                           for d in sorted(os.listdir(os.path.join(HERE, "hidden")))]
NAMES = ["1", "h_1", "h_2", "sqrt(h_2)", "u", "u*h_1", "sign(d)sqrt|d|"]
BALANCE_NAMES = ["1", "h_1", "h_2", "u", "u*h_1", "q"]
THRESHOLD = 0.05
WINDOW = 31


def read(path):
    rows = list(csv.DictReader(open(path)))
    col = lambda k: np.array([float(r[k]) for r in rows])  # noqa: E731
    return col("t_s"), col("h_1_mm"), col("h_2_mm"), col("Q_p_mL_s"), col("Q_out_mL_s")


def features(h_1, h_2, u):
    d = h_1 - h_2
    return np.column_stack([np.ones_like(h_1), h_1, h_2, np.sqrt(np.clip(h_2, 0.0, None)), u, u * h_1,
                            np.sign(d) * np.sqrt(np.abs(d))])


def identify(folder):
    """Both regressions on the two runs of a data set: (per-tank coefficients and rms, mass
    balance coefficients and rms)."""
    smoother = ps.SmoothedFiniteDifference(smoother_kws={"window_length": WINDOW, "polyorder": 3})
    thetas, rates, balances, totals = [], [], [], []
    for run in ("step_1.csv", "step_2.csv"):
        t, h_1, h_2, u, q = read(os.path.join(folder, run))
        x_dot = smoother._differentiate(np.column_stack([h_1, h_2]), t)
        keep = slice(15, -15)  # the smoother's ends are one-sided
        # The terms are smoothed by the same filter as the rates (Savitzky-Golay is linear, so
        # a relation linear in the terms survives it exactly; filtering one side only smears
        # each step of the pump over the window and fakes terms that lag it).
        thetas.append(smooth(features(h_1, h_2, u))[keep])
        rates.append(x_dot[keep])
        balances.append(smooth(np.column_stack([np.ones_like(h_1), h_1, h_2, u, u * h_1, q]))[keep])
        totals.append(x_dot[keep].sum(axis=1, keepdims=True))
    out = []
    for theta, rate in ((np.vstack(thetas), np.vstack(rates)), (np.vstack(balances), np.vstack(totals))):
        coef = sparse_fit(theta, rate)
        out.append((coef, np.sqrt(np.mean((theta @ coef.T - rate) ** 2, axis=0))))
    return out


def smooth(columns):
    return savgol_filter(columns, WINDOW, 3, axis=0)


def sparse_fit(theta, rate):
    """STLSQ on columns scaled to unit RMS and each rate to unit RMS, so that the threshold
    is the smallest contribution a term may make, as a fraction of the rate's RMS."""
    column_scale = np.sqrt(np.mean(theta**2, axis=0))
    rate_scale = np.sqrt(np.mean(rate**2, axis=0))
    optimizer = ps.STLSQ(threshold=THRESHOLD, alpha=1e-6)
    optimizer.fit(theta / column_scale, rate / rate_scale)
    return optimizer.coef_ * rate_scale[:, None] / column_scale[None, :]


def equation(coefficients, names=NAMES):
    terms = [f"{c:+.4g} {n}" for c, n in zip(coefficients, names) if c != 0.0]
    return " ".join(terms) if terms else "0"


def main():
    print(f"pysindy: STLSQ threshold {THRESHOLD} (of each rate's RMS, terms scaled to unit RMS), "
          f"Savitzky-Golay derivatives ({WINDOW} samples, order 3); h in mm, u and q in mL/s, t in s")
    for label, folder in SETS:
        (coef, rms), (balance, balance_rms) = identify(folder)
        print(f"\n{label}:")
        print(f"  dh_1/dt = {equation(coef[0])}    (rms {rms[0]:.3g} mm/s)")
        print(f"  dh_2/dt = {equation(coef[1])}    (rms {rms[1]:.3g} mm/s)")
        print(f"  d(h_1 + h_2)/dt = {equation(balance[0], BALANCE_NAMES)}    (rms {balance_rms[0]:.3g} mm/s)")
        print(f"    mass balance: net term in the levels (h_1 + h_2 coefficients) {balance[0][1] + balance[0][2]:+.2e} 1/s "
              f"(a leak from tank 1: -G_l rho g/A_1), u*h_1 {balance[0][4]:+.2e} (pump sag: -0.1 s_p rho g/1000)")


if __name__ == "__main__":
    main()
