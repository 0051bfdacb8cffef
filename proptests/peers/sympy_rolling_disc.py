#!/usr/bin/env python3
"""sympy.physics.mechanics on the rolling disc, judged by `dcad check` (issue 13).

Three ways to get the disc's equations of motion with sympy, all with the kinematics of sympy's
rolling-disc examples (yaw q1, lean q2, spin q3; inertia m r²/4, m r²/2, m r²/4):

  documented   "A rolling disk using the Lagrange method": Euler–Lagrange equations of T − V in
               (q1, q2, q3), the centre's velocity from Dmc.v2pt_theory(C, N, R) with C at rest, and
               the potential as printed (−m g r cos q2);
  sign-fixed   the same with V = +m g r cos q2 (the centre's height): isolates the method;
  constrained  LagrangesMethod on (x, y, q1, q2, q3) with the rolling constraints as nonholonomic
               constraints (what sympy issue 27631 says the example should do).

Each gives q'' at a point of the constraint space; the script turns that into a dcad result (point and
velocity of every variable of cases/rolling-disc-3d.json: x'' and y'' by differentiating the rolling
constraints, p' = d/dt ∂L/∂v along the motion) and runs `dcad check`.  Expected: 3, 3, 0 (the documented
method leaves out the curvature term of YM (5.6): Euler–Lagrange on L_c is wrong for nonholonomic
constraints; with the constraints sympy agrees with dcad).
    /usr/bin/python3 proptests/peers/sympy_rolling_disc.py DCAD CASE OUTDIR
prints one line per route: name, dcad check's exit code, the accelerations.
"""
import json
import os
import subprocess
import sys

import sympy as sm
import sympy.physics.mechanics as me

t = me.dynamicsymbols._t
x, y, q1, q2, q3 = me.dynamicsymbols('x y q1 q2 q3')
m, g, r = sm.Rational(2), sm.Rational(981, 100), sm.Rational(1, 2)
N = me.ReferenceFrame('N')
Y = N.orientnew('Y', 'Axis', [q1, N.z])
L = Y.orientnew('L', 'Axis', [q2, Y.x])
R = L.orientnew('R', 'Axis', [q3, L.y])
I = me.inertia(L, m / 4 * r**2, m / 2 * r**2, m / 4 * r**2)

# the point: lean 0.4 rad, turning and spinning; x', y' from the rolling constraints
Q0 = {x: sm.Rational(1, 3), y: sm.Rational(-1, 2), q1: sm.Rational(3, 10), q2: sm.Rational(2, 5), q3: sm.Rational(1, 5)}
QD0 = {q1.diff(t): sm.Rational(1, 2), q2.diff(t): sm.Rational(-3, 10), q3.diff(t): sm.Rational(3)}
QD0[x.diff(t)] = r * sm.cos(Q0[q1]) * QD0[q3.diff(t)]
QD0[y.diff(t)] = r * sm.sin(Q0[q1]) * QD0[q3.diff(t)]
ROLL = [x.diff(t) - r * sm.cos(q1) * q3.diff(t), y.diff(t) - r * sm.sin(q1) * q3.diff(t)]


def full_lagrangian():
    """T − V with the contact point's coordinates (the case file's L, before substitution)."""
    vD = x.diff(t) * N.x + y.diff(t) * N.y + (r * L.z).dt(N)
    w = R.ang_vel_in(N)
    return m / 2 * vD.dot(vD) + sm.Rational(1, 2) * w.dot(I.dot(w)) - m * g * r * sm.cos(q2)


def angles_only(potential_sign):
    """The documented example: Euler–Lagrange in (q1, q2, q3), C at rest."""
    C = me.Point('C')
    C.set_vel(N, 0)
    Dmc = C.locatenew('Dmc', r * L.z)
    Dmc.v2pt_theory(C, N, R)
    body = me.RigidBody('BodyD', Dmc, R, m, (I, Dmc))
    body.potential_energy = potential_sign * m * g * r * sm.cos(q2)
    lm = me.LagrangesMethod(me.Lagrangian(N, body), [q1, q2, q3])
    lm.form_lagranges_equations()
    rhs = solve_at_point(lm)  # [q', q'']
    acc = {q.diff(t, 2): rhs[3 + i] for i, q in enumerate([q1, q2, q3])}
    # x'' and y'' follow from the rolling constraints differentiated
    for c, var in zip(ROLL, [x, y]):
        acc[var.diff(t, 2)] = sm.solve(c.diff(t), var.diff(t, 2))[0]
    return acc


def solve_at_point(lm):
    """lm.rhs() at the point: M z = F with the point's values substituted first, to 40 digits (a
    symbolic inverse of the mass matrix, or exact trigonometric numbers, take minutes)."""
    at = lambda e: e.subs(QD0).subs(Q0).evalf(40)  # 40 digits: the comparison is in double
    return sm.Matrix(at(lm.mass_matrix_full)).LUsolve(sm.Matrix(at(lm.forcing_full)))


def constrained():
    lm = me.LagrangesMethod(full_lagrangian(), [x, y, q1, q2, q3], nonhol_coneqs=ROLL)
    lm.form_lagranges_equations()
    rhs = solve_at_point(lm)  # [q', q'', multipliers]
    return {q.diff(t, 2): rhs[5 + i] for i, q in enumerate([x, y, q1, q2, q3])}


def result(acc):
    """A dcad result for cases/rolling-disc-3d.json: point (q, v, p) and velocity of each."""
    qs, names = [x, y, q1, q2, q3], ['x', 'y', 'q1', 'q2', 'q3']
    lag = full_lagrangian()
    # the accelerations at the point (they may depend on q'' of the others: substitute iteratively)
    a = {}
    for k in range(3):
        for q in qs:
            e = acc[q.diff(t, 2)].subs({qq.diff(t, 2): a.get(qq, qq.diff(t, 2)) for qq in qs})
            a[q] = sm.N(e.subs(QD0).subs(Q0), 40)
    point, vel = {}, {}
    for q, n in zip(qs, names):
        point[n] = repr(float(sm.N(Q0[q], 20)))
        point['v_' + n] = repr(float(sm.N(QD0[q.diff(t)], 20)))
        vel[n] = point['v_' + n]
        vel['v_' + n] = repr(float(sm.N(a[q], 20)))
    for q, n in zip(qs, names):
        p = lag.diff(q.diff(t))
        point['p_' + n] = repr(float(sm.N(p.subs(QD0).subs(Q0), 20)))
        pdot = p.diff(t).subs({qq.diff(t, 2): a[qq] for qq in qs}).subs(QD0).subs(Q0)
        vel['p_' + n] = repr(float(sm.N(pdot, 20)))
    return {"dcad": 1, "name": "rolling-disc-3d", "dims": [15, 8], "steps": 1, "consistent": True, "solution_rank": 0, "unique": True,
            "point": point, "velocity": vel}, [float(sm.N(a[q], 12)) for q in [q1, q2, q3]]


def main():
    dcad, case, out = sys.argv[1:4]
    os.makedirs(out, exist_ok=True)
    for name, acc in (("documented", angles_only(-1)), ("sign-fixed", angles_only(+1)), ("constrained", constrained())):
        res, qdd = result(acc)
        path = os.path.join(out, f"sympy-{name}.json")
        with open(path, "w") as f:
            json.dump(res, f, indent=1)
        rc = subprocess.run([dcad, "check", path, case], capture_output=True, text=True)
        print(name, rc.returncode, "q1''=%.12g q2''=%.12g q3''=%.12g" % tuple(qdd), (rc.stdout + rc.stderr).strip().splitlines()[-1])


if __name__ == "__main__":
    main()
