#!/usr/bin/env python3
"""Side by side with scipy: the pendulum and the damped Duffing oscillator over 10 s, with
solve_ivp (LSODA and Radau, analytic Jacobian, the tolerance bondgraph's integrator uses:
rtol 1e-10), against `bondgraph simulate` measured by criterion
(`cargo bench -p bondgraph-solver --bench nonlinear`).

Run it from anywhere: it makes its own virtual environment in benches/peers/.venv with
scipy from PyPI, times each solver (median of 20 runs) and prints the ratio to the
criterion medians given on the command line (or read from target/criterion).

    python3 benches/peers/scipy_compare.py
"""

import math
import statistics
import time

from peers import criterion_median, ensure_venv

def models():
    m, l, g = 1.0, 1.0, 9.81
    k, k3, b = 1.0, 5.0, 0.1

    def pendulum(t, x):
        p, q = x
        return [-m * g * l * math.sin(q), p / (m * l * l)]

    def pendulum_jac(t, x):
        return [[0.0, -m * g * l * math.cos(x[1])], [1.0 / (m * l * l), 0.0]]

    def duffing(t, x):
        p, q = x
        return [-b / m * p - k * q - k3 * q ** 3, p / m]

    def duffing_jac(t, x):
        return [[-b / m, -k - 3 * k3 * x[1] ** 2], [1.0 / m, 0.0]]

    return [
        ("nonlinear_pendulum_10s", pendulum, pendulum_jac, [0.0, 2.0]),
        ("nonlinear_duffing_10s", duffing, duffing_jac, [0.0, 1.5]),
    ]

def main():
    ensure_venv()
    import numpy as np
    from scipy.integrate import solve_ivp

    t_eval = np.linspace(0.0, 10.0, 101)
    print(f"{'model':34} {'solver':6} {'median':>10} {'bondgraph':>10} {'ratio':>7}")
    for name, f, jac, x0 in models():
        ours = criterion_median(name)
        for method in ["LSODA", "Radau"]:
            times = []
            for _ in range(20):
                start = time.perf_counter()
                solution = solve_ivp(f, (0.0, 10.0), x0, method=method, jac=jac, rtol=1e-10, atol=1e-13, t_eval=t_eval)
                times.append(time.perf_counter() - start)
                assert solution.success, solution.message
            median = statistics.median(times)
            ratio = f"{median / ours:7.0f}" if ours else "      ?"
            ours_text = f"{ours * 1e3:8.3f}ms" if ours else "         ?"
            print(f"{name:34} {method:6} {median * 1e3:8.2f}ms {ours_text} {ratio}")


if __name__ == "__main__":
    main()
