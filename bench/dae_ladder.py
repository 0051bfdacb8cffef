#!/usr/bin/env python3
"""The dae form at size (issue 30's benchmark goals): an RC ladder in MNA form driven by a voltage source
V(t) = sin(t) at its first node, 1 nF at every node (so a capacitor sits across the source: index 2),
1 kOhm between neighbours; n nodes, n + 1 variables (node voltages and the source current).  Sparse data,
dense solvers.  Prints one table row per size and backend, side by side, from one run:

    /usr/bin/python3 bench/dae_ladder.py build/dcad 100 400 1000

Every run must give dims [n+1, n, n-1], steps 2, index 2 (checked here; a wrong answer is a failure)."""
import json, subprocess, sys, tempfile, time


def ladder(n):
    N = n + 1
    E = [["0"] * N for _ in range(N)]
    A = [["0"] * N for _ in range(N)]
    f = ["0"] * N
    for k in range(n):
        E[k][k] = "1e-9"
        nb = [j for j in (k - 1, k + 1) if 0 <= j < n]
        A[k][k] = f"-{len(nb)}/1000"
        for j in nb:
            A[k][j] = "1/1000"
    A[0][n] = "-1"
    A[n][0] = "1"
    f[n] = "-sin(t)"
    return {"dcad": 1, "name": f"rc-ladder-{n}", "variables": [f"e{k + 1}" for k in range(n)] + ["i"],
            "dae": {"E": E, "A": A, "f": f, "time": "t"}}


def main():
    dcad = sys.argv[1]
    sizes = [int(s) for s in sys.argv[2:]] or [100, 400, 1000]
    print("| variables | backend | seconds | dims (first 3) | steps | index | certified |")
    print("|---|---|---|---|---|---|---|")
    bad = 0
    for n in sizes:
        with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as fh:
            json.dump(ladder(n), fh)
        for backend in ("reference", "fast"):
            t0 = time.perf_counter()
            out = subprocess.run([dcad, "solve", fh.name, "--backend", backend, "--json"], capture_output=True, text=True)
            dt = time.perf_counter() - t0
            r = json.loads(out.stdout)
            ok = r["dims"] == [n + 1, n, n - 1] and r["steps"] == 2 and r.get("index") == 2
            bad += not ok
            print(f"| {n + 1} | {backend} | {dt:.2f} | {r['dims'][:3]} | {r['steps']} | {r.get('index')} | {r['certified']} |"
                  + ("" if ok else " WRONG"))
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
