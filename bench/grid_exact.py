#!/usr/bin/python3
"""Independent oracle for bench/sparse_simulate.sh: the K x K RLC power grid of that script, written by
hand as an ODE (grid node voltages v and segment currents i; each segment is R in series with L),
   C dv/dt = sum of segment currents in - out + (1.2 - v_11)/Rs [node 1,1] - Iload(t) [node K,K]
   L di/dt = v_a - v_b - R i,
from the DC operating point (v = 1.2 V, i = 0), propagated exactly between output rows by one dense
matrix exponential (scipy.linalg.expm) of the system augmented with the load's piecewise-linear
exosystem.  No dcad code: a different formulation (no contractions, no Krylov) of the same circuit.
Usage: grid_exact.py K STEPS  -> CSV t,v_K_K,i_Rs on the grid t = k * 10 ps."""
import sys
import numpy as np
from scipy.linalg import expm

K, steps = int(sys.argv[1]), int(sys.argv[2])
h, C, R, L, Rs, Vdd = 10e-12, 100e-12, 50e-3, 1e-9, 10e-3, 1.2
node = lambda i, j: i * K + j
segs = [(node(i, j), node(i, j + 1)) for i in range(K) for j in range(K - 1)] + \
       [(node(i, j), node(i + 1, j)) for i in range(K - 1) for j in range(K)]
nv, ns = K * K, len(segs)
N = nv + ns + 3  # + [one, a, b]: Vdd's constant, the load a with slope b
one, a, b = nv + ns, nv + ns + 1, nv + ns + 2
M = np.zeros((N, N))
for s, (p, q) in enumerate(segs):
    M[p, nv + s] -= 1 / C
    M[q, nv + s] += 1 / C
    M[nv + s, p] += 1 / L
    M[nv + s, q] -= 1 / L
    M[nv + s, nv + s] -= R / L
M[0, 0] -= 1 / (Rs * C)
M[0, one] += Vdd / (Rs * C)
M[node(K - 1, K - 1), a] -= 1 / C
M[a, b] = 1
E = expm(M * h)

def load(t):  # PULSE(0 1 1n 100p 100p 2n 10n), one period within 10 ns
    if t < 1e-9: return 0.0
    if t < 1.1e-9: return (t - 1e-9) / 100e-12
    if t < 3.1e-9: return 1.0
    if t < 3.2e-9: return 1 - (t - 3.1e-9) / 100e-12
    return 0.0

z = np.zeros(N)
z[:nv] = Vdd
z[one] = 1
print("t,v_%d_%d,i_Rs" % (K, K))
for k in range(steps + 1):
    t = k * h
    print("%.17g,%.17g,%.17g" % (t, z[node(K - 1, K - 1)], (Vdd - z[0]) / Rs))
    z[a] = load(t)
    z[b] = (load(t + h) - load(t)) / h  # corners fall on the grid: linear on (t, t + h)
    z = E @ z
