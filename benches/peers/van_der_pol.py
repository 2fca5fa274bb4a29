#!/usr/bin/env python3
"""The work of a library Radau5 on the stiff Van der Pol oscillator, for the comparison in
`bondgraph-solver/src/ode/radau.rs` (`van_der_pol_is_solved_with_the_work_of_a_library_radau5`).

y1' = y2, y2' = ((1 - y1^2) y2 - y1)/eps, eps = 1e-6, y(0) = (2, 0), t in [0, 2]: the IVP
test set's `vdpol`, whose published reference is y(2) = (1.706167732170483,
-0.8928097010247975). scipy's Radau follows Hairer and Wanner's RADAU5 (simplified Newton,
Jacobian kept while Newton contracts fast, Gustafsson's step control) on the tolerance as
given, where RADAU5 and bondgraph's Radau IIA hold the error to 0.1 rtol^(2/3). Prints, for
each tolerance, the largest relative error against the reference and scipy's counts of f
evaluations, Jacobians and LU decompositions.

    python3 benches/peers/van_der_pol.py     (needs numpy and scipy)
"""

import numpy as np
from scipy.integrate import solve_ivp

EPS = 1e-6
REFERENCE = np.array([1.706167732170483, -0.8928097010247975])


def f(_, y):
    return [y[1], ((1 - y[0] ** 2) * y[1] - y[0]) / EPS]


def jacobian(_, y):
    return [[0, 1], [(-2 * y[0] * y[1] - 1) / EPS, (1 - y[0] ** 2) / EPS]]


def main():
    for rtol in [1e-4, 1e-6, 7e-7, 5e-7, 3e-7, 1e-8]:
        r = solve_ivp(f, (0, 2), [2.0, 0.0], method="Radau", jac=jacobian, rtol=rtol, atol=rtol)
        error = np.max(np.abs((r.y[:, -1] - REFERENCE) / REFERENCE))
        print(f"rtol {rtol:g}: error {error:.2e}, f {r.nfev}, Jacobians {r.njev}, LU {r.nlu}")


if __name__ == "__main__":
    main()
