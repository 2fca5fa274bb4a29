# Independent reference for held_nonlinear.rs: the dragged Karnopp block,
# m v' = F(t) - F_C - c v|v| while sliding, from breakaway at t0 = 2/3 s (F = 3t reaches
# F_S = 2 N), integrated by classical RK4 with fine steps (checked by halving the step),
# then the closed-form stop after the push ends at 2.5 s:
# v' = -1 - 0.1 v^2 gives v = sqrt(10) tan(atan(v0/sqrt(10)) - (t - 2.5)/sqrt(10)).
import math
def F(t):
    if t < 1: return 3*t
    if t < 2: return 3.0
    if t < 2.5: return 3 - 6*(t-2)
    return 0.0
def f(t, v): return F(t) - 1 - 0.1*v*abs(v)
def integrate(t0, t1, v, n):
    h = (t1-t0)/n; t = t0
    for _ in range(n):
        k1=f(t,v); k2=f(t+h/2,v+h/2*k1); k3=f(t+h/2,v+h/2*k2); k4=f(t+h,v+h*k3)
        v += h/6*(k1+2*k2+2*k3+k4); t += h
    return v
def v_at(t, n_per_unit):
    # integrate piecewise between the input's breakpoints (smooth pieces)
    pts = [2/3, 1.0, 2.0, 2.5]
    v = 0.0
    for a, b in zip(pts, pts[1:]):
        if t <= a: break
        e = min(b, t)
        v = integrate(a, e, v, max(1, int(round((e-a)*n_per_unit))))
    return v
for n in (20000, 40000):
    v25 = v_at(2.5, n)
    stop = 2.5 + math.sqrt(10)*math.atan(v25/math.sqrt(10))
    print(n, repr(v25), repr(stop), repr(v_at(1.5, n)))
