"""The flagship's four Fig. 6 events, derived by hand and integrated with scipy.

Independent of the Rust code: the robot's equations in each mode, written out with the tip's
parasitic mass (5e-15 kg) and the catheter's servo time constant (m_ct/(K_p + b/4) = 1e-8 s)
taken as instantaneous, so each mode is an algebraic velocity and one integral.

  t1: the tip breaks away when A P_s + 2 F_C_ct = F_S_ge (the catheter, slipping ahead,
      drags the inner structure with F_C_ct, which pulls the tip with twice that).
  t2: the tip slides at v_ge = (A P_s + 2 F_C_ct - F_C_ge)/b; the catheter (at
      v_ct_des - F_C_ct/K_p) sticks when 2 v_ge enters the dead band below it.
  t3: stuck, 2 v_ge = v_ct = (K_p v_ct_des - F_C_ge/2 + A P_s/2)/(K_p + b/4); the inner
      structure, slack by the channel's lead, is taut again when the integral of
      2 v_ge - v_ac from 0 comes back to zero.
  t4: taut, v_ge = (A P_s - F_C_ge + 2 K_p v_ct_des - 2 f_k)/(b + 4 K_p) with
      df_k/dt = k_ge (2 v_ge - v_ac); the catheter slips when K_p (v_ct_des - 2 v_ge)
      reaches F_S_ct.

Run: python3 studies/eversion/scripts/fig6_events.py
With the ceiling (110 kPa from t = 0.11 s): 0.0070 0.019931 0.130417 0.154085
Without it:                                  0.0070 0.019931 0.130002 0.166097
"""

from scipy.integrate import quad, solve_ivp
from scipy.optimize import brentq

A, FS, FC, b = 1e-4, 11.7, 9.125, 1250.0
FSc, FCc, K, k = 6.05, 5.5, 5e4, 5e5
vac, vd, dv = 5.8e-3, 6.3e-3, 1e-6


def events(ceiling):
    P = (lambda t: min(1e6 * t, 1.1e5)) if ceiling else (lambda t: 1e6 * t)
    t1 = (FS - 2 * FCc) / (A * 1e6)
    slide = lambda t: (A * P(t) + 2 * FCc - FC) / b
    t2 = brentq(lambda t: 2 * slide(t) - (vd - FCc / K - dv), t1, 1.0)
    stretch = -vac * t1 + quad(lambda t: 2 * slide(t) - vac, t1, t2, points=[0.11])[0]
    stuck = lambda t: (K * vd - FC / 2 + A * P(t) / 2) / (K + b / 4)
    q = lambda T: stretch + quad(lambda t: stuck(t) - vac, t2, T, points=[0.11], limit=200)[0]
    t3 = brentq(q, t2 + 1e-6, 1.0)
    C = lambda t: A * P(t) - FC + 2 * K * vd
    v2 = lambda t, f: 2 * (C(t) - 2 * f) / (b + 4 * K)
    slip = lambda t, f: K * (vd - v2(t, f[0])) - FSc
    slip.terminal = True
    run = solve_ivp(lambda t, f: [k * (v2(t, f[0]) - vac)], [t3, 1.0], [0.0],
                    events=slip, rtol=1e-12, atol=1e-14, max_step=1e-4)
    return t1, t2, t3, run.t_events[0][0]


if __name__ == "__main__":
    for ceiling in (True, False):
        print("with the ceiling" if ceiling else "without it", *("%.6f" % t for t in events(ceiling)))
