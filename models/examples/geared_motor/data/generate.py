"""Synthetic steady speeds of the geared motor, from known parameter values.

Written independently of the Rust code, from the closed form of the steady state (see
geared_motor.ron): with alpha = N K / R_a and beta = N^2 K^2 / R_a,

    w = (alpha V - T_C - tau) / (b + beta)   if alpha V - tau > T_S (the shaft breaks away),
    w = 0                                     otherwise (stalled: the encoder reads no counts).

The truth: K = 0.05 N m/A, b = 0.05 N m s/rad, T_C = 0.15 N m, T_S = 0.3 N m, with the model
file's R_a = 2 ohm and N = 20 (geared_motor.ron holds other values of the fitted parameters, so
that a calibration has to find these). Noise: Gaussian, 0.05 rad/s, numpy seed 11, added to
turning rows only.

Run from the repository root: python3 models/examples/geared_motor/data/generate.py
"""

import numpy as np

R_a, N = 2.0, 20.0
K, b, T_C, T_S = 0.05, 0.05, 0.15, 0.3
SIGMA = 0.05

alpha, beta = N * K / R_a, N * N * K * K / R_a
rng = np.random.default_rng(11)
rows = [(v, None) for v in [0.4, 0.5, 0.8, 1.0, 2.0, 4.0, 6.0, 9.0, 12.0, 15.0, 18.0, 24.0]]
rows += [(v, tau) for tau in [1000.0, 2000.0, 4000.0] for v in [12.0, 18.0, 24.0]]
rows += [(1.0, 400.0)]
lines = ["V_V,tau_mNm,w_rad_s"]
for v, tau_mNm in rows:
    tau = 0.0 if tau_mNm is None else tau_mNm * 1e-3
    drive = alpha * v - tau
    w = (drive - T_C) / (b + beta) + SIGMA * rng.standard_normal() if drive > T_S else 0.0
    lines.append(f"{v:g},{'' if tau_mNm is None else f'{tau_mNm:g}'},{w:.4f}")
path = "models/examples/geared_motor/data/steady.csv"
with open(path, "w") as f:
    f.write("\n".join(lines) + "\n")
print(path, len(rows), "rows")
