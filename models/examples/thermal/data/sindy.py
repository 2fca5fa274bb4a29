"""A data-driven identifier on the same runs: SINDy (pysindy's STLSQ, smoothed derivatives).

For each data set (the base truth and each hidden effect, runs step_1.csv and step_2.csv
together), the blocks' rates of temperature (K/s) are estimated by pysindy's
SmoothedFiniteDifference (Savitzky-Golay, 15 samples of 20 s, order 3) and regressed by
pysindy's STLSQ (terms scaled to unit RMS, threshold 10 % of the rate's RMS; the terms smoothed
by the same filter) on a library of terms in the rises x_i = T_i - T_amb (K), the heater
powers P_1, P_2 (W) and the radiation-like term r = (T1^4 - T_amb^4)/1e8 (K^4):

    x_1, x_2, P_1, P_2, r, x_1^(5/4)

Both temperatures are measured, so the base model is inside the library:
dx_1/dt = -(1/R_12 + 1/R_1a)/C_1 x_1 + x_2/(C_1 R_12) + P_1/C_1 and likewise for block 2.
What each hidden effect should leave:

    radiation            a term in r in dx_1/dt: -1e8 eA sigma/C_1 = -1.26e-4 K/s per 1e8 K^4
    heater-lead-loss     the P_1 coefficient (1 - eta_h)/C_1: the network's reciprocity
                         (C_1 a_12 = C_2 a_21 = 1/R_12) gives 1 - eta_h = a_21 b_11/(a_12 b_22)
    contact-resistance   smaller coupling terms (a refit of R_12, as for the physical model)

Run from the repository root: python3 models/examples/thermal/data/sindy.py
"""

import csv
import os

import numpy as np
import pysindy as ps
from scipy.signal import savgol_filter

HERE = os.path.dirname(os.path.abspath(__file__))
SETS = [("base", HERE)] + [(d, os.path.join(HERE, "hidden", d))
                           for d in sorted(os.listdir(os.path.join(HERE, "hidden")))]
NAMES = ["x_1", "x_2", "P_1", "P_2", "r", "x_1^(5/4)"]
THRESHOLD = 0.1
WINDOW = 15


def read(path):
    rows = list(csv.DictReader(open(path)))
    col = lambda k: np.array([float(r[k]) for r in rows])  # noqa: E731
    return col("t_s"), col("T_1_K"), col("T_2_K"), col("P_1_W"), col("P_2_W"), col("T_amb_K")


def smooth(columns):
    return savgol_filter(columns, WINDOW, 3, axis=0)


def sparse_fit(theta, rate):
    """STLSQ on terms scaled to unit RMS and each rate to unit RMS."""
    column_scale = np.sqrt(np.mean(theta**2, axis=0))
    rate_scale = np.sqrt(np.mean(rate**2, axis=0))
    optimizer = ps.STLSQ(threshold=THRESHOLD, alpha=1e-6)
    optimizer.fit(theta / column_scale, rate / rate_scale)
    return optimizer.coef_ * rate_scale[:, None] / column_scale[None, :]


def identify(folder):
    smoother = ps.SmoothedFiniteDifference(smoother_kws={"window_length": WINDOW, "polyorder": 3})
    thetas, rates = [], []
    for run in ("step_1.csv", "step_2.csv"):
        t, t_1, t_2, p_1, p_2, t_amb = read(os.path.join(folder, run))
        x_1, x_2 = t_1 - t_amb, t_2 - t_amb
        x_dot = smoother._differentiate(np.column_stack([x_1, x_2]), t)
        keep = slice(WINDOW // 2, -(WINDOW // 2))
        theta = np.column_stack([x_1, x_2, p_1, p_2, (t_1**4 - t_amb**4) / 1e8,
                                 np.sign(x_1) * np.abs(x_1) ** 1.25])
        thetas.append(smooth(theta)[keep])
        rates.append(x_dot[keep])
    theta, rate = np.vstack(thetas), np.vstack(rates)
    coef = sparse_fit(theta, rate)
    return coef, np.sqrt(np.mean((theta @ coef.T - rate) ** 2, axis=0))


def equation(coefficients):
    terms = [f"{c:+.4g} {n}" for c, n in zip(coefficients, NAMES) if c != 0.0]
    return " ".join(terms) if terms else "0"


def main():
    print(f"pysindy: STLSQ threshold {THRESHOLD} (of each rate's RMS, terms scaled to unit RMS), "
          f"Savitzky-Golay derivatives ({WINDOW} samples, order 3); x in K, P in W, t in s")
    c_1, c_2, r_12, r_1a, r_2a = 450.0, 900.0, 0.8, 4.0, 2.5
    print("base truth: dx_1/dt = %+.4g x_1 %+.4g x_2 %+.4g P_1;  dx_2/dt = %+.4g x_1 %+.4g x_2 %+.4g P_2"
          % (-(1 / r_12 + 1 / r_1a) / c_1, 1 / (c_1 * r_12), 1 / c_1,
             1 / (c_2 * r_12), -(1 / r_12 + 1 / r_2a) / c_2, 1 / c_2))
    for label, folder in SETS:
        coef, rms = identify(folder)
        print(f"\n{label}:")
        print(f"  dx_1/dt = {equation(coef[0])}    (rms {rms[0]:.3g} K/s)")
        print(f"  dx_2/dt = {equation(coef[1])}    (rms {rms[1]:.3g} K/s)")
        if coef[0][1] != 0.0 and coef[1][3] != 0.0:
            print(f"    reciprocity: 1 - eta_h = a_21 b_11/(a_12 b_22) = "
                  f"{coef[1][0] * coef[0][2] / (coef[0][1] * coef[1][3]):.4f}")


if __name__ == "__main__":
    main()
