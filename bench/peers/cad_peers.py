#!/usr/bin/env python3
"""The CAD of a presymplectic system (D = graph ω, E_D = everything, CEF §5 / Gotay–Nester) by
three peers, on the exact instances dcad_sweep wrote (instances.jsonl): the same linear-algebra
steps as dcad's reference (cad.hpp), with each peer's own rank and null-space routines:

  sympy   exact (Matrix over QQ: rank, nullspace)             Debian python3-sympy
  numpy   double SVD, σ > max(m, n)·ε·s zero-tolerance             python3-numpy
  scipy   double QR with column pivoting, |R_ii| > max(m, n)·ε·s    python3-scipy

s is the 2-norm of the input (max of ‖ω‖, ‖H‖), as in dcad's fast backend.  numpy's own default
(σ > max(m, n)·ε·σ₁ of each matrix) is worse here: a row that is pure rounding has rank 1.

Tower:  M_0 = Q^n;  W_k = T M_k;  W_k^ω = {u : ω(w, u) = 0 ∀ w ∈ W_k};
        M_{k+1} = {x ∈ M_k : ⟨H x + g, u⟩ = 0 ∀ u ∈ W_k^ω};  solution rank = dim(ker ω ∩ T M_c).
Writes CSV rows in dcad_sweep's format (family,param,n,method,instances,wrong,…) to stdout.
Run with Debian's interpreter: /usr/bin/python3 cad_peers.py instances.jsonl [--sympy-max-n N]
"""
import json
import math
import sys
import time
from collections import defaultdict

import numpy as np
import scipy.linalg
import sympy

EPS = np.finfo(float).eps


class Numpy:
    name = "numpy"
    scale = 1.0  # the input's 2-norm, set per instance

    @staticmethod
    def convert(rows):
        return np.array([[float(sympy.Rational(x)) for x in r] for r in rows], dtype=float)

    @staticmethod
    def rank(m):
        return 0 if m.size == 0 else int(np.linalg.matrix_rank(m, tol=max(m.shape) * EPS * Numpy.scale))

    @staticmethod
    def null(m, n):
        if m.shape[0] == 0:
            return np.eye(n)
        _, s, vt = np.linalg.svd(m)
        tol = max(m.shape) * EPS * Numpy.scale
        r = int(np.sum(s > tol))
        return vt[r:].T

    @staticmethod
    def stack(a, b):
        return np.vstack([a, b])

    @staticmethod
    def to_float(m):
        return np.asarray(m, dtype=float)


class Scipy(Numpy):
    name = "scipy"

    @staticmethod
    def rank(m):
        if m.size == 0:
            return 0
        _, r, _ = scipy.linalg.qr(m, pivoting=True, mode="economic")
        d = np.abs(np.diag(r))
        return int(np.sum(d > max(m.shape) * EPS * Numpy.scale))

    @staticmethod
    def null(m, n):
        if m.shape[0] == 0:
            return np.eye(n)
        q, r, _ = scipy.linalg.qr(m.T, pivoting=True)  # range(mᵀ) = first rank columns of Q
        d = np.abs(np.diag(r))
        k = int(np.sum(d > max(m.shape) * EPS * Numpy.scale))
        return q[:, k:]


class Sympy:
    name = "sympy"

    @staticmethod
    def convert(rows):
        return sympy.Matrix([[sympy.Rational(x) for x in r] for r in rows])

    @staticmethod
    def rank(m):
        return 0 if m.rows == 0 or m.cols == 0 else m.rank()

    @staticmethod
    def null(m, n):
        if m.rows == 0:
            return sympy.eye(n)
        vs = m.nullspace()
        return sympy.Matrix.hstack(*vs) if vs else sympy.zeros(n, 0)

    @staticmethod
    def stack(a, b):
        return sympy.Matrix.vstack(a, b)

    @staticmethod
    def to_float(m):
        return np.array(m.tolist(), dtype=float).reshape(m.rows, m.cols)


def cad(p, omega, hessian):
    """dims, solution rank, T M_k bases (as float) by peer p; g = 0 in every presymplectic family."""
    n = omega.shape[0]
    eqs = None  # rows a of M_k = {a x = 0}
    basis = sympy.eye(n) if p is Sympy else np.eye(n)
    dims, tower = [n], [p.to_float(basis)]
    while True:
        wo = (basis.T * omega) if p is Sympy else basis.T @ omega  # rows: ω(w, ·) for w in a basis of W_k
        u = p.null(wo, n)                                             # columns: a basis of W_k^ω
        cand = (u.T * hessian) if p is Sympy else u.T @ hessian       # rows: ⟨H x, u⟩ = 0
        fresh = 0
        for i in range(cand.shape[0]):
            row = cand[i:i + 1, :]
            new = row if eqs is None else p.stack(eqs, row)
            if p.rank(new) > (0 if eqs is None else p.rank(eqs)):
                eqs, fresh = new, fresh + 1
        if fresh == 0:
            break
        basis = p.null(eqs, n)
        dims.append(basis.shape[1])
        tower.append(p.to_float(basis))
    kw = (omega * basis) if p is Sympy else omega @ basis
    return dims, basis.shape[1] - p.rank(kw), tower


def angle(a, b):
    if a.shape[1] != b.shape[1]:
        return math.pi / 2
    if a.shape[1] == 0:
        return 0.0
    qa, _ = np.linalg.qr(a)
    qb, _ = np.linalg.qr(b)
    s = np.linalg.svd(qb - qa @ (qa.T @ qb), compute_uv=False)
    return math.asin(min(1.0, s[0] if s.size else 0.0))


def one_case(path):
    """--one FILE: the sympy CAD on one dcad case file (presymplectic ω, Hessian), as a process of its own."""
    with open(path) as f:
        case = json.load(f)
    dims, srank, _ = cad(Sympy, Sympy.convert(case["dirac"]["presymplectic"]), Sympy.convert(case["energy"]["hessian"]))
    print(json.dumps({"dims": dims, "solution_rank": srank}))


def main():
    args = sys.argv[1:]
    if not args:
        sys.exit(__doc__)
    if args[0] == "--one":
        return one_case(args[1])
    sympy_max_n = 1 << 30
    if "--sympy-max-n" in args:
        i = args.index("--sympy-max-n")
        sympy_max_n = int(args[i + 1])
        del args[i:i + 2]
    acc = defaultdict(lambda: {"n": 0, "count": 0, "wrong": 0, "angle": 0.0, "seconds": 0.0})
    with open(args[0]) as f:
        lines = [json.loads(l) for l in f if l.strip()]
    for k, inst in enumerate(lines):
        n = len(inst["omega"])
        exact = [np.array(t, dtype=float).reshape(n, -1) for t in inst["tower"]]
        for p in (Numpy, Scipy, Sympy):
            if p is Sympy and n > sympy_max_n:
                continue
            t0 = time.perf_counter()
            omega, hessian = p.convert(inst["omega"]), p.convert(inst["hessian"])
            if p is not Sympy:
                Numpy.scale = max(np.linalg.norm(omega, 2), np.linalg.norm(hessian, 2), 1e-300)
            dims, srank, tower = cad(p, omega, hessian)
            dt = time.perf_counter() - t0
            a = acc[(inst["family"], inst["param"], p.name)]
            a["n"], a["count"], a["seconds"] = n, a["count"] + 1, a["seconds"] + dt
            bad = dims != inst["dims"] or srank != inst["solution_rank"]
            a["wrong"] += bad
            a["angle"] = max(a["angle"], math.pi / 2 if bad and dims != inst["dims"] else
                             max((angle(t, e) for t, e in zip(tower, exact)), default=0.0))
        if (k + 1) % 20 == 0 or k + 1 == len(lines):
            print(f"\r[peers] {k + 1}/{len(lines)} instances", end="", file=sys.stderr)
    print(file=sys.stderr)
    for (family, param, name), a in acc.items():
        print(f"{family},{param:g},{a['n']},{name},{a['count']},{a['wrong']},{a['wrong']},0,0,{a['angle']:g},{a['seconds'] / a['count']:g}")


if __name__ == "__main__":
    main()
