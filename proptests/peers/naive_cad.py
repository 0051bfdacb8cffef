#!/usr/bin/env python3
"""A deliberately naive, independent CAD for LC netlists (standard library only), used to show how
another implementation is validated with `dcad check` (README, "Validate your implementation").

It follows the closed form of CEF §6 with Gauss-Jordan elimination in double precision and a fixed
absolute pivot tolerance of 1e-9 -- the textbook approach, and exactly what goes wrong on circuits
with values far from 1 (a 1 pH inductor looks like a wire), which `dcad check` then reports (exit 3).

    python3 naive_cad.py deck.cir > result.json && dcad check result.json deck.cir
"""
import json
import sys

TOL = 1e-9
SUFFIX = {"f": 1e-15, "p": 1e-12, "n": 1e-9, "u": 1e-6, "m": 1e-3, "k": 1e3, "meg": 1e6, "g": 1e9, "t": 1e12}


def value(text):
    t = text.lower()
    for s in ("meg", "f", "p", "n", "u", "m", "k", "g", "t"):
        i = len(t)
        while i > 0 and t[i - 1].isalpha():
            i -= 1
        if t[i:].startswith(s):
            return float(t[:i]) * SUFFIX[s]
    return float(t.rstrip("abcdefghijklmnopqrstuvwxyz") or t)


def read(path):
    branches, nodes = [], {}
    with open(path) as f:
        lines = f.read().splitlines()[1:]
    for line in lines:
        tok = line.split()
        if not tok or tok[0][0] in "*.+":
            continue
        kind = tok[0][0].upper()
        ends = []
        for name in tok[1:3]:
            name = name.lower()
            ends.append(-1 if name in ("0", "gnd") else nodes.setdefault(name, len(nodes)))
        v = value(tok[4] if tok[3].lower() == "dc" and len(tok) > 4 else tok[3])
        if kind == "L" and v == 0:
            kind = "V"
        branches.append((kind, ends[0], ends[1], v))
    return branches, len(nodes)


def rref(rows, ncols):
    m = [list(r) for r in rows]
    pivots, r = [], 0
    for c in range(ncols):
        p = max(range(r, len(m)), key=lambda i: abs(m[i][c]), default=None)
        if p is None or abs(m[p][c]) <= TOL:
            continue
        m[r], m[p] = m[p], m[r]
        m[r] = [x / m[r][c] for x in m[r]]
        for i in range(len(m)):
            if i != r and m[i][c] != 0:
                f = m[i][c]
                m[i] = [a - f * b for a, b in zip(m[i], m[r])]
        pivots.append(c)
        r += 1
        if r == len(m):
            break
    return m[:r], pivots


def nullspace(rows, ncols):
    r, pivots = rref(rows, ncols)
    free = [c for c in range(ncols) if c not in pivots]
    basis = []
    for f in free:
        v = [0.0] * ncols
        v[f] = 1.0
        for i, p in enumerate(pivots):
            v[p] = -r[i][f]
        basis.append(v)
    return basis


def main(path):
    branches, nnodes = read(path)
    n = len(branches)
    k = [[0.0] * n for _ in range(nnodes)]
    for b, (_, a, c, _) in enumerate(branches):
        if a >= 0:
            k[a][b] += 1
        if c >= 0:
            k[c][b] -= 1
    phi = [v if kind == "L" else 0.0 for kind, _, _, v in branches]
    psi = [1 / v if kind == "C" else 0.0 for kind, _, _, v in branches]

    def s_of(u):  # ψ⁻¹(φ(U) + Δ°) as the rows ψρ, ρ ∈ (φ(U) + Δ°)°
        rho = nullspace([[phi[i] * x[i] for i in range(n)] for x in u] + k, n)
        return [[psi[i] * x[i] for i in range(n)] for x in rho]

    delta = nullspace(k, n)
    dims = [3 * n, n + len(delta)]
    prev = delta
    while True:
        q_rows = s_of(prev)
        dim_s = n - len(rref(q_rows, n)[0])
        nxt = nullspace(k + q_rows, n)
        for d in (dim_s + len(prev), dim_s + len(nxt)):  # M_2k, M_2k+1 (CEF §6)
            if d == dims[-1]:
                break
            dims.append(d)
        else:
            prev = nxt
            continue
        break
    z = prev  # M_c has v in this Δ_j whether c is odd or even
    rank = len(rref([[sum(dv[i] * phi[i] * zv[i] for i in range(n)) for zv in z] for dv in delta], len(z))[0]) if z else 0
    sol = len(z) - rank
    json.dump({"dcad": 1, "backend": "naive-python", "certified": False, "dims": dims, "steps": len(dims) - 1,
               "consistent": True, "solution_rank": sol, "unique": sol == 0,
               "circuit": {"branches": n, "nodes": nnodes + 1}}, sys.stdout)
    print()


if __name__ == "__main__":
    main(sys.argv[1])
