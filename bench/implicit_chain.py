#!/usr/bin/python3
"""The implicit form at size: a chain of K pendulum links in Cartesian coordinates (index 3),
N = 5K variables (x_i, y_i, u_i, w_i, lam_i), each link at a generic angle on a rational point of
the circle (3-4-5, 5-12-13, 8-15-17, 7-24-25 triangles), at rest.  By hand: M_1 = the K length
constraints, M_2 their derivatives, M_3 fixes the K multipliers: dims [5K, 4K, 3K, 2K], index 3.
Times `dcad solve --json` on every backend, one run, side by side.

usage: bench/implicit_chain.py DCAD K [K ...]    (writes the cases under /tmp)"""
import json, subprocess, sys, time

TRIANGLES = [(3, 4, 5), (5, 12, 13), (8, 15, 17), (7, 24, 25)]


def case(k):
    names, eqs, init = [], [], {}
    for i in range(1, k + 1):
        names += [f"x{i}", f"y{i}", f"u{i}", f"w{i}", f"lam{i}"]
    px, py = "0", "0"
    from fractions import Fraction
    x, y = Fraction(0), Fraction(0)
    for i in range(1, k + 1):
        a, b, c = TRIANGLES[i % len(TRIANGLES)]
        x += Fraction(a, c)
        y -= Fraction(b, c)
        init[f"x{i}"], init[f"y{i}"] = str(x), str(y)
        xp = "0" if i == 1 else f"x{i-1}"
        yp = "0" if i == 1 else f"y{i-1}"
        nx = "" if i == k else f" - lam{i+1}*(x{i+1} - x{i})"
        ny = "" if i == k else f" - lam{i+1}*(y{i+1} - y{i})"
        eqs += [f"v_x{i} - u{i}", f"v_y{i} - w{i}", f"v_u{i} + lam{i}*(x{i} - {xp}){nx}",
                f"v_w{i} + lam{i}*(y{i} - {yp}){ny} + g", f"(x{i} - {xp})^2 + (y{i} - {yp})^2 - 1"]
    return {"dcad": 1, "name": f"pendulum-chain-{k}", "parameters": {"g": "981/100"},
            "implicit": {"coordinates": names, "equations": eqs}, "initial": init,
            "expect": {"dims": [5 * k, 4 * k, 3 * k, 2 * k], "steps": 3, "index": 3}}


def main():
    dcad, ks = sys.argv[1], [int(a) for a in sys.argv[2:]]
    print("| links | variables | backend | seconds | dims | index | certified |")
    print("|---|---|---|---|---|---|---|")
    for k in ks:
        path = f"/tmp/implicit-chain-{k}.json"
        with open(path, "w") as f:
            json.dump(case(k), f)
        for backend in ["reference", "fast", "certified"]:
            t0 = time.perf_counter()
            p = subprocess.run([dcad, "solve", path, "--backend", backend, "--json"], capture_output=True, text=True, timeout=3600)
            dt = time.perf_counter() - t0
            if p.returncode != 0:
                print(f"| {k} | {5*k} | {backend} | {dt:.2f} | exit {p.returncode}: {p.stderr.strip()[:80]} | | |")
                continue
            j = json.loads(p.stdout)
            ok = j["dims"] == [5 * k, 4 * k, 3 * k, 2 * k]
            print(f"| {k} | {5*k} | {backend} | {dt:.2f} | {j['dims']}{'' if ok else ' (WRONG)'} | {j.get('index')} | {j['certified']} |")
            sys.stdout.flush()


if __name__ == "__main__":
    main()
