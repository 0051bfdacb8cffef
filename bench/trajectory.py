#!/usr/bin/env python3
"""Trajectory error against run time on the 4-port of CEF §6 (cases/lc-4port.cir), dcad simulate
against ngspice at several reltol, both against the analytic solution (issue 6, chart 4).

The deck is one loop: L1 = 2 in series with C1 ∥ C3 = 3 + 7 and C2 = 5, V_C1 = V_C3 = 1, V_C2 = 2,
i_L(0) = 0.  With S = V_C1 + V_C2 (= V_1), L i' = −S and S' = i / C_s, C_s = 1/(1/10 + 1/5) = 10/3:
    i_L(t) = −(S_0 / (L ω)) sin ω t,   ω = 1/√(L C_s),   S_0 = 3.
Error = max |i_L − exact| / max |exact| on the output grid (step 1 ms, t ≤ 10: 10,001 points).
ngspice chooses its own steps and linearizes onto the grid: reltol 1e-3 … 1e-10 with tmax 100 ms
(reltol decides), then tmax 1 ms … 10 µs at reltol 1e-10 (the step bound decides: trapezoidal
error ~ (ω h)²/12, so ngspice needs h ≈ 5 µs to reach what dcad's exact flow gives at any step).
Times: wall time of the whole process (read, solve, integrate, write), best of 3.
    python3 bench/trajectory.py DCAD_BINARY CASES_DIR OUT_CSV
"""
import math
import os
import subprocess
import sys
import tempfile
import time

L, CS, S0 = 2.0, 10.0 / 3.0, 3.0
W = 1.0 / math.sqrt(L * CS)


def exact(t):
    return -(S0 / (L * W)) * math.sin(W * t)


def error(rows):
    ref = max(abs(exact(t)) for t, _ in rows)
    return max(abs(i - exact(t)) for t, i in rows) / ref


def best_of(n, fn):
    best, out = float("inf"), None
    for _ in range(n):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def run_dcad(dcad, deck, step, tmp):
    csv = os.path.join(tmp, "dcad.csv")
    subprocess.run([dcad, "simulate", deck, "--tstop", "10", "--step", repr(step), "--csv", csv],
                   check=True, stderr=subprocess.DEVNULL)
    with open(csv) as f:
        head = f.readline().strip().split(",")
        k = head.index("v_L1")
        return [(float(r[0]), float(r[k])) for r in (line.split(",") for line in f)]


def run_ngspice(deck_lines, reltol, tmax, tmp):
    data = os.path.join(tmp, "ng.txt")
    deck = os.path.join(tmp, "ng.cir")
    with open(deck, "w") as f:
        f.write("".join(deck_lines))
        f.write(f".options reltol={reltol} abstol=1e-15 vntol=1e-12\n.tran 1m 10 0 {tmax} uic\n.control\nset numdgt=16\nrun\n"
                f"linearize i(l1)\nwrdata {data} i(l1)\n.endc\n.end\n")
    if os.path.exists(data):
        os.remove(data)
    subprocess.run(["ngspice", "-b", deck], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    rows = []
    if os.path.exists(data):
        with open(data) as f:
            for line in f:
                p = line.split()
                if len(p) >= 2:
                    rows.append((float(p[0]), float(p[1])))
    return rows


def main():
    dcad, cases, out = sys.argv[1:4]
    deck = os.path.join(cases, "lc-4port.cir")
    with open(deck) as f:
        body = [l for l in f if not l.lower().startswith((".tran", ".end"))]
    lines = ["tool,setting,points,seconds,max_rel_error\n"]
    with tempfile.TemporaryDirectory() as tmp:
        for step in (1e-2, 1e-3, 1e-4):
            secs, rows = best_of(3, lambda: run_dcad(dcad, deck, step, tmp))
            lines.append(f"dcad,step={step:g},{len(rows)},{secs:.6g},{error(rows):.3g}\n")
            print(lines[-1], end="", file=sys.stderr)
        settings = [(r, "100m") for r in ("1e-3", "1e-4", "1e-5", "1e-6", "1e-7", "1e-8", "1e-9", "1e-10")]
        settings += [("1e-10", t) for t in ("1m", "100u", "10u")]
        for reltol, tmax in settings:
            secs, rows = best_of(3 if tmax in ("100m", "1m") else 1, lambda: run_ngspice(body, reltol, tmax, tmp))
            err = error(rows) if len(rows) >= 10001 else float("nan")
            lines.append(f"ngspice,reltol={reltol} tmax={tmax},{len(rows)},{secs:.6g},{err:.3g}\n")
            print(lines[-1], end="", file=sys.stderr)
    with open(out, "w") as f:
        f.writelines(lines)


if __name__ == "__main__":
    main()
