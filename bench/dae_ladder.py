#!/usr/bin/env python3
"""The dae form at size (issue 30's benchmark goals): an RC ladder in MNA form driven by a voltage source
V(t) = sin(t) at its first node, 1 nF at every node (so a capacitor sits across the source: index 2),
1 kOhm between neighbours; n nodes, n + 1 variables (node voltages and the source current).  Sparse data,
dense solvers.  Prints one table row per size and backend, side by side, from one run:

    /usr/bin/python3 bench/dae_ladder.py build/dcad 100 1000 10000 100000

E and A go in the sparse encoding; beyond 2,000 variables the reference refuses (it holds E and A densely), certified
takes its sparse route (modular elimination, every null vector verified exactly) and fast its own.

Every run must give dims [n+1, n, n-1], steps 2, index 2 (checked here; a wrong answer is a failure)."""
import json, subprocess, sys, tempfile, time


def ladder(n, floating=False):
    """The case in the sparse encoding of E and A ({"rows": m, "entries": [[row, column, value], ...]}).
    floating: also 1 nF between nodes k and k + 1 for every k = 1 mod 3 (E's node block is then no
    diagonal, but still positive definite: the same tower, reached through dense left null vectors)."""
    N = n + 1
    E, A = [], []
    f = ["0"] * N
    for k in range(n):
        if floating and k % 3 == 1 and k + 1 < n:
            E.append([k, k, "2e-9"])
            E.append([k, k + 1, "-1e-9"])
            E.append([k + 1, k, "-1e-9"])
        elif floating and k % 3 == 2:
            E.append([k, k, "2e-9"])
        else:
            E.append([k, k, "1e-9"])
        nb = [j for j in (k - 1, k + 1) if 0 <= j < n]
        A.append([k, k, f"-{len(nb)}/1000"])
        for j in nb:
            A.append([k, j, "1/1000"])
    A.append([0, n, "-1"])
    A.append([n, 0, "1"])
    f[n] = "-sin(t)"
    return {"dcad": 1, "name": f"rc-ladder-{n}", "variables": [f"e{k + 1}" for k in range(n)] + ["i"],
            "dae": {"E": {"rows": N, "entries": E}, "A": {"rows": N, "entries": A}, "f": f, "time": "t"}}


def main():
    dcad = sys.argv[1]
    sizes = [int(s) for s in sys.argv[2:]] or [100, 400, 1000]
    print("| variables | capacitors | backend | seconds | dims (first 3) | steps | index | certified |")
    print("|---|---|---|---|---|---|---|---|")
    bad = 0
    for n, floating in [(n, fl) for n in sizes for fl in (False, True)]:
        with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as fh:
            json.dump(ladder(n, floating), fh)
        for backend in ("reference", "fast", "certified"):
            if backend == "reference" and (n + 1) ** 2 > 4_000_000:
                continue  # beyond the dense exact route (DaeCase::dense_limit): it refuses, as it should (certified takes its sparse route)
            t0 = time.perf_counter()
            out = subprocess.run([dcad, "solve", fh.name, "--backend", backend, "--json"], capture_output=True, text=True)
            dt = time.perf_counter() - t0
            r = json.loads(out.stdout)
            ok = r["dims"] == [n + 1, n, n - 1] and r["steps"] == 2 and r.get("index") == 2
            bad += not ok
            print(f"| {n + 1} | {'floating too' if floating else 'to ground'} | {backend} | {dt:.2f} | {r['dims'][:3]} | {r['steps']} | {r.get('index')} | {r['certified']} |"
                  + ("" if ok else " WRONG"))
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
