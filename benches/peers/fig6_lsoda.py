#!/usr/bin/env python3
"""Side by side with scipy's LSODA on the flagship's Fig. 6 run, the one that
`cargo bench -p bondgraph-solver --bench simulate` times as `fig6_robot_0.2s`: the robot of
`models/eversion/robot.ron` from the tip held and the catheter slipping, the tank pressure
ramped at 1 MPa/s (no ceiling, as the bench has it), 0.2 s, the tip's speed and displacement,
the inner structure's tension and the catheter contact's force sampled every millisecond.

The equations of the five modes the run passes through are written out here as
`bondgraph equations models/eversion/robot.ron --mode ...` prints them (energy variables:
the tip's momentum p_ge with its 5e-15 kg parasitic mass, the inner structure's stretch q_k,
the catheter's momentum p_ct; a fourth state integrates the tip's speed). Each mode is
integrated by `solve_ivp(method="LSODA")` with its constant Jacobian, and its guards are
solve_ivp's terminal events; where the catheter sticks, the two momenta merge into
p = p_ge + 2 p_ct (storage 4 m_ct + m_ge), and split again where it slips. Every guard that
bondgraph watches in a mode is watched here too.

LSODA stops with "illegal input" within 1e-16 s of the tip's breakaway, in local time or
not, in momenta or in velocities: it cannot take the tip's 4e-18 s time constant; scipy's
BDF and Radau (the stiff solvers LSODA switches to) run it, and are timed instead.

Run it from anywhere: it makes its own virtual environment in benches/peers/.venv with
scipy from PyPI (as scipy_compare.py does), prints the event times at each tolerance beside
bondgraph's (from `target/release/bondgraph simulate`, if built) and the independent hand
derivation of `studies/eversion/scripts/fig6_events.py` (0.0070, 0.019931, 0.130002,
0.166097 s without the ceiling), and the median time of 20 runs against criterion's median
of the bench (`target/criterion/fig6_robot_0.2s`, if it has run).

    cargo bench -p bondgraph-solver --bench simulate -- fig6
    python3 benches/peers/fig6_lsoda.py
"""

import json
import os
import statistics
import subprocess
import tempfile
import time
import warnings

from peers import ROOT, criterion_median, ensure_venv

# models/eversion/robot.ron's parameters.
M_GE, K_GE, AREA = 5e-15, 5e5, 1e-4
FS_GE, FC_GE, B = 11.7, 9.125, 1250.0
FS_CT, FC_CT, M_CT, K_P, DV = 6.05, 5.5, 5e-4, 5e4, 1e-6
V_AC, V_CT_DES = 5.8e-3, 6.3e-3
MERGED = 4 * M_CT + M_GE
DURATION, SAMPLE = 0.2, 1e-3
HAND = [0.0070, 0.019931, 0.130002, 0.166097]

def shifted(event, start):
    """An event function of a mode's own time, as solve_ivp calls it."""

    def local(tau, x):
        return event(start + tau, x)

    local.terminal, local.direction = event.terminal, event.direction
    return local


def pressure(t):
    return 1e6 * t


def guard(f, direction):
    """A guard as a terminal event, crossing zero upwards (+1) or downwards (-1)."""
    f.terminal = True
    f.direction = direction
    return f


# Each mode: (states, right-hand side, Jacobian, guards as (name, event function, next mode)).
# State vectors: 'separate' is (p_ge, q_k, p_ct, x_ge), 'merged' (p, q_k, x_ge).


def held():
    """fr_ge=stuck,k=slack,fr_ct=slip-: the tip held (p_ge = 0)."""

    def rhs(t, x):
        return [0.0, -V_AC, -K_P / M_CT * x[2] + K_P * V_CT_DES - FC_CT, 0.0]

    jac = [[0, 0, 0, 0], [0, 0, 0, 0], [0, 0, -K_P / M_CT, 0], [0, 0, 0, 0]]
    guards = [
        ("tip breaks away", guard(lambda t, x: AREA * pressure(t) + 2 * FC_CT - FS_GE, 1), "sliding"),
        ("taut", guard(lambda t, x: x[1], 1), None),
        ("catheter sticks", guard(lambda t, x: -x[2] / M_CT + DV, 1), None),
    ]
    return "separate", rhs, jac, guards


def sliding(taut):
    """fr_ge=slip+,k=slack|taut,fr_ct=slip-: both slide."""
    spring = K_GE if taut else 0.0

    def rhs(t, x):
        p_ge, q_k, p_ct, _ = x
        return [
            -B / M_GE * p_ge - 2 * spring * q_k + AREA * pressure(t) + 2 * FC_CT - FC_GE,
            2 / M_GE * p_ge - V_AC,
            -K_P / M_CT * p_ct + K_P * V_CT_DES - FC_CT,
            p_ge / M_GE,
        ]

    jac = [
        [-B / M_GE, -2 * spring, 0, 0],
        [2 / M_GE, 0, 0, 0],
        [0, 0, -K_P / M_CT, 0],
        [1 / M_GE, 0, 0, 0],
    ]
    guards = [
        ("tip sticks", guard(lambda t, x: x[0] / M_GE - DV, -1), None),
        ("slack" if taut else "taut", guard(lambda t, x: x[1], -1 if taut else 1), None),
        ("catheter sticks", guard(lambda t, x: 2 * x[0] / M_GE - x[2] / M_CT + DV, 1), "carried_taut" if taut else "carried"),
    ]
    return "separate", rhs, jac, guards


def carried(taut):
    """fr_ge=slip+,k=slack|taut,fr_ct=stuck: the catheter carried at twice the tip's speed."""
    spring = K_GE if taut else 0.0

    def holding(t, x):
        p, q_k, _ = x
        return (
            2 * (-B * M_CT + K_P * M_GE) / MERGED**2 * p
            - 4 * spring * M_CT / MERGED * q_k
            + 2 * AREA * M_CT / MERGED * pressure(t)
            - K_P * M_GE / MERGED * V_CT_DES
            - 2 * FC_GE * M_CT / MERGED
        )

    def rhs(t, x):
        p, q_k, _ = x
        return [
            -(B + 4 * K_P) / MERGED * p - 2 * spring * q_k + AREA * pressure(t) + 2 * K_P * V_CT_DES - FC_GE,
            2 / MERGED * p - V_AC,
            p / MERGED,
        ]

    jac = [[-(B + 4 * K_P) / MERGED, -2 * spring, 0], [2 / MERGED, 0, 0], [1 / MERGED, 0, 0]]
    guards = [
        ("tip sticks", guard(lambda t, x: x[0] / MERGED - DV, -1), None),
        ("slack" if taut else "taut", guard(lambda t, x: x[1], -1 if taut else 1), None if taut else "carried_taut"),
        ("catheter slips forward", guard(lambda t, x: holding(t, x) - FS_CT, 1), None),
        ("catheter slips back", guard(lambda t, x: holding(t, x) + FS_CT, -1), "sliding_taut" if taut else None),
    ]
    return "merged", rhs, jac, guards


MODES = {
    "held": held,
    "sliding": lambda: sliding(False),
    "sliding_taut": lambda: sliding(True),
    "carried": lambda: carried(False),
    "carried_taut": lambda: carried(True),
}


def convert(x, frm, to):
    """A state handed from one mode to the next: momenta merged or split at the event."""
    if frm == to:
        return list(x)
    if to == "merged":  # (p_ge, q_k, p_ct, x_ge) -> (p, q_k, x_ge)
        return [x[0] + 2 * x[2], x[1], x[3]]
    v = x[0] / MERGED  # (p, q_k, x_ge) -> (p_ge, q_k, p_ct, x_ge)
    return [M_GE * v, x[1], M_CT * 2 * v, x[2]]


def run(method, rtol):
    """The whole run by `method`: its event times, and the samples' outputs."""
    from scipy.integrate import solve_ivp

    mode, layout = "held", "separate"
    x = [0.0, 0.0, M_CT * 6.19e-3, 0.0]
    t = 0.0
    events, samples = [], []
    scales = {"separate": [M_GE * 1e-2, 1e-3, M_CT * 1e-2, 1e-3], "merged": [MERGED * 1e-2, 1e-3, 1e-3]}
    while t < DURATION:
        layout, rhs, jac, guards = MODES[mode]()
        # Each mode in its own time from its start: the tip's 4e-18 s transient as it breaks
        # away is some ulps of t = 7 ms, and LSODA stops there ("illegal input") when its
        # steps fall below t's rounding.
        t_eval = [k * SAMPLE - t for k in range(round(DURATION / SAMPLE) + 1) if k * SAMPLE >= t]
        start = t
        solution = solve_ivp(
            lambda tau, x: rhs(start + tau, x),
            (0.0, DURATION - t),
            x,
            method=method,
            jac=jac,
            rtol=rtol,
            atol=[rtol * s for s in scales[layout]],
            t_eval=t_eval,
            events=[shifted(g[1], start) for g in guards],
        )
        if not solution.success:
            raise RuntimeError(f"{solution.message} in mode '{mode}', entered at t = {start:.6f} s")
        samples.append(solution.y)
        fired = [k for k, times in enumerate(solution.t_events) if len(times) > 0]
        if not fired:
            break
        k = min(fired, key=lambda k: solution.t_events[k][0])
        name, _, following = guards[k]
        assert following is not None, f"{name} at t = {start + solution.t_events[k][0]} in {mode}: not in Fig. 6"
        t = start + solution.t_events[k][0]
        events.append(t)
        nxt = MODES[following]()[0]
        x = convert(solution.y_events[k][0], layout, nxt)
        mode = following
    return events, samples


def bondgraph_events():
    binary = os.path.join(ROOT, "target", "release", "bondgraph")
    if not os.path.exists(binary):
        return None
    with open(os.path.join(ROOT, "models", "eversion", "fig6.ron")) as f:
        text = f.read().replace('"P_s": Ramp(slope: 1.0e6, ceiling: 1.1e5)', '"P_s": Ramp(slope: 1.0e6)')
    with tempfile.NamedTemporaryFile("w", suffix=".ron", delete=False) as f:
        f.write(text)
    out = subprocess.run(
        [binary, "simulate", os.path.join(ROOT, "models", "eversion", "robot.ron"), "--scenario", f.name, "--format", "json"],
        capture_output=True, text=True, check=True,
    ).stdout
    os.unlink(f.name)
    document, _ = json.JSONDecoder().raw_decode(out)
    return [e["t"] for e in document["events"]]

def main():
    ensure_venv()
    warnings.simplefilter("ignore")  # LSODA's own warning repeats its failure
    ours = criterion_median("fig6_robot_0.2s")
    reference = bondgraph_events()
    print("events (s):")
    print(f"  {'hand derivation':18}", " ".join(f"{t:.6f}" for t in HAND))
    if reference:
        print(f"  {'bondgraph':18}", " ".join(f"{t:.9f}" for t in reference))
    print(f"{'solver':6} {'rtol':6} {'median':>10} {'bondgraph':>10} {'ratio':>7}  events; largest difference from bondgraph")
    for method in ["LSODA", "BDF", "Radau"]:
        for rtol in [1e-3, 1e-6, 1e-8]:
            try:
                events, _ = run(method, rtol)
            except RuntimeError as error:
                print(f"{method:6} {rtol:<6.0e} fails: {error}")
                continue
            times = []
            for _ in range(20):
                start = time.perf_counter()
                run(method, rtol)
                times.append(time.perf_counter() - start)
            median = statistics.median(times)
            ratio = f"{median / ours:7.0f}" if ours else "      ?"
            ours_text = f"{ours * 1e6:8.1f}us" if ours else "         ?"
            same = reference and len(events) == len(reference)
            worst = max(abs(a - b) for a, b in zip(events, reference)) if same else float("nan")
            shown = " ".join(f"{t:.6f}" for t in events)
            print(f"{method:6} {rtol:<6.0e} {median * 1e3:8.2f}ms {ours_text} {ratio}  {shown}; {worst:.1e} s")

if __name__ == "__main__":
    main()
