"""A data-driven identifier on the same runs: SINDy (pysindy's STLSQ, smoothed derivatives).

For each data set (the base truth and each hidden effect, runs step_1.csv and step_2.csv
together), two sparse regressions with pysindy's STLSQ (terms scaled to unit RMS, threshold
2 % of the target's RMS), derivatives by pysindy's SmoothedFiniteDifference (Savitzky-Golay,
7 samples of 1 ms, order 3) with the terms smoothed by the same filter:

- the carriage's acceleration dv/dt (mm/s^2) on the samples where it slides (|v| > 3 mm/s,
  7 ms or more from a stop), on the library
      i, v, sign(v), F_L, sign(v)*F_L, sign(v)*exp(-|v|/10)
  (A, mm/s, N; the last a velocity-weakening bump over 10 mm/s). Base truth, with the rotor
  merged into the carriage (M = m + J_m/n_s^2 = 25.69 kg): 1000 (K/n_s i - F_L - b v/1000
  - F_C sign(v))/M = +1468 i - 1.557 v - 389.3 sign(v) - 38.93 F_L.
- the armature's voltage balance, an algebraic relation because the electrical mode
  (L_a/R_a = 0.33 ms) is faster than the 1 ms samples can follow: V on the samples 5 ms or
  more after a change of the voltage, on the library
      i, v, sign(i), di/dt
  Base truth: V = 1.2 i + 0.0377 v (+ 4e-4 di/dt); a brush drop adds U_b sign(i).

What each hidden effect should leave: Stribeck weakening a sign(v)*exp(-|v|/10) term (of the
kind, not the law: the truth is piecewise linear); load-dependent friction a sign(v)*F_L
term (-38.93 mu_L); a brush drop a sign(i) term in the voltage (U_b); the seal drag a
larger v coefficient (a refit, as for the physical model).

Run from the repository root: python3 models/examples/actuator/data/sindy.py
"""

import csv
import os

import numpy as np
import pysindy as ps
from scipy.signal import savgol_filter

HERE = os.path.dirname(os.path.abspath(__file__))
SETS = [("base", HERE)] + [(d, os.path.join(HERE, "hidden", d))
                           for d in sorted(os.listdir(os.path.join(HERE, "hidden")))]
MECHANICAL = ["i", "v", "sign(v)", "F_L", "sign(v)*F_L", "sign(v)*exp(-|v|/10)"]
ELECTRICAL = ["i", "v", "sign(i)", "di/dt"]
THRESHOLD = 0.02
WINDOW = 7


def read(path):
    rows = list(csv.DictReader(open(path)))
    col = lambda k: np.array([float(r[k]) for r in rows])  # noqa: E731
    return col("t_s"), col("V_V"), col("F_L_N"), col("v_mm_s"), col("i_mA") / 1000.0


def smooth(columns):
    return savgol_filter(columns, WINDOW, 3, axis=0)


def sparse_fit(theta, target):
    column_scale = np.sqrt(np.mean(theta**2, axis=0))
    target_scale = np.sqrt(np.mean(target**2))
    optimizer = ps.STLSQ(threshold=THRESHOLD, alpha=1e-6)
    optimizer.fit(theta / column_scale, target / target_scale)
    coef = optimizer.coef_[0] * target_scale / column_scale
    return coef, np.sqrt(np.mean((theta @ coef - target) ** 2))


def near(mask, width):
    """Samples within `width` samples after (or around) any sample of mask."""
    out = np.zeros_like(mask)
    for k in np.flatnonzero(mask):
        out[max(0, k - width):k + width + 1] = True
    return out


def identify(folder):
    smoother = ps.SmoothedFiniteDifference(smoother_kws={"window_length": WINDOW, "polyorder": 3})
    mech, accel, elec, volts = [], [], [], []
    for run in ("step_1.csv", "step_2.csv"):
        t, voltage, f_l, v, i = read(os.path.join(folder, run))
        rates = smoother._differentiate(np.column_stack([v, i]), t)
        sv = np.sign(v)
        theta_m = smooth(np.column_stack([i, v, sv, f_l, sv * f_l, sv * np.exp(-np.abs(v) / 10.0)]))
        sliding = (np.abs(v) > 3.0) & ~near(v == 0.0, WINDOW)
        sliding[: WINDOW // 2] = sliding[-(WINDOW // 2):] = False
        mech.append(theta_m[sliding])
        accel.append(rates[sliding, 0])
        theta_e = smooth(np.column_stack([i, v, np.sign(i), rates[:, 1]]))
        changed = np.abs(np.diff(voltage, prepend=voltage[0])) > 0.0
        settled = ~near(changed, 5)
        settled[: WINDOW // 2] = settled[-(WINDOW // 2):] = False
        elec.append(theta_e[settled])
        volts.append(smooth(voltage)[settled])
    return sparse_fit(np.vstack(mech), np.concatenate(accel)), sparse_fit(np.vstack(elec), np.concatenate(volts))


def equation(coefficients, names):
    terms = [f"{c:+.4g} {n}" for c, n in zip(coefficients, names) if c != 0.0]
    return " ".join(terms) if terms else "0"


def main():
    print(f"pysindy: STLSQ threshold {THRESHOLD} (of the target's RMS, terms scaled to unit RMS), "
          f"Savitzky-Golay derivatives ({WINDOW} samples, order 3); v in mm/s, i in A, V in V, F_L in N, t in s")
    print("base truth: dv/dt = +1468 i -1.557 v -389.3 sign(v) -38.93 F_L;  V = +1.2 i +0.0377 v (+0.0004 di/dt)")
    for label, folder in SETS:
        (mech, mech_rms), (elec, elec_rms) = identify(folder)
        print(f"\n{label}:")
        print(f"  dv/dt = {equation(mech, MECHANICAL)}    (rms {mech_rms:.3g} mm/s^2)")
        print(f"  V     = {equation(elec, ELECTRICAL)}    (rms {elec_rms:.3g} V)")


if __name__ == "__main__":
    main()
