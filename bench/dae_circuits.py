#!/usr/bin/python3
"""The dae form on circuit DAEs at size, every backend side by side in one run (issue 30): RC ladders in MNA form
(node voltages e_1..e_n and the current i of a voltage source V(t) = sin t at node 1), n nodes, a resistor between
neighbours and from the last node to ground, in three families:

  grounded  a capacitor to ground at every node (1 nF, 1 kOhm):                 by hand dims [n+1, n, n-1], index 2
  half      a capacitor to ground at every other node (nodes 1, 3, 5, ...):    by hand [n+1, n/2, n/2 - 1], index 2
            (M_1: KCL at the n/2 nodes without one, and e_1 = V; M_2: i from node 1's KCL)
  graded    as half, values drawn from 1 mOhm ... 1 MOhm and 1 pF ... 1 mF, and a floating capacitor between nodes
            3k+2 and 3k+3: no hand-derived tower — certified's (exact) is the yardstick; fast is marked WRONG
            where it differs.

    /usr/bin/python3 bench/dae_circuits.py build/dcad 1000 10000 100000

reference runs up to 2,000 variables (its dense limit); fast gets a 300 s timeout per run; every run 12 GiB of memory."""
import json, random, resource, subprocess, sys, tempfile, time
from fractions import Fraction as F


def circuit(n, family, seed=1):
    rnd = random.Random(seed)
    N = n + 1
    E, A = {}, {}

    def add(D, i, j, v):
        D[(i, j)] = D.get((i, j), 0) + v

    def g():
        return 1 / F(10) ** rnd.randint(-3, 6) if family == "graded" else F(1, 1000)

    def c():
        return F(1, 10) ** rnd.randint(3, 12) if family == "graded" else F(1, 10**9)

    for k in range(n):
        gk = g()
        j = k + 1 if k + 1 < n else None
        add(A, k, k, -gk)
        if j is not None:
            add(A, j, j, -gk), add(A, k, j, gk), add(A, j, k, gk)
        if family == "grounded" or k % 2 == 0:
            add(E, k, k, c())
        if family == "graded" and k % 3 == 1 and k + 1 < n:
            ck = c()
            add(E, k, k, ck), add(E, k + 1, k + 1, ck), add(E, k, k + 1, -ck), add(E, k + 1, k, -ck)
    add(A, 0, n, F(-1)), add(A, n, 0, F(1))
    f = ["0"] * N
    f[n] = "-sin(t)"
    enc = lambda D: {"rows": N, "entries": [[i, j, str(v)] for (i, j), v in sorted(D.items()) if v != 0]}
    return {"dcad": 1, "name": f"{family}-{n}", "variables": [f"e{k + 1}" for k in range(n)] + ["i"],
            "dae": {"E": enc(E), "A": enc(A), "f": f, "time": "t"}}


def limit_memory():
    """12 GiB of address space per run: a run that needs more fails (and says so) instead of taking the machine."""
    resource.setrlimit(resource.RLIMIT_AS, (12 << 30, 12 << 30))


def by_hand(n, family):
    if family == "grounded":
        return [n + 1, n, n - 1]
    if family == "half":
        return [n + 1, n // 2, n // 2 - 1] if n % 2 == 0 else None
    return None


def main():
    dcad = sys.argv[1]
    sizes = [int(s) for s in sys.argv[2:]] or [1000, 10000]
    print("| variables | family | backend | seconds | dims | index | certified | right |")
    print("|---|---|---|---|---|---|---|---|")
    for n in sizes:
        for family in ("grounded", "half", "graded"):
            with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as fh:
                json.dump(circuit(n, family), fh)
            want = by_hand(n, family)
            exact = None
            for backend in ("certified", "reference", "fast"):
                if backend == "reference" and n + 1 > 2000:
                    continue
                t0 = time.perf_counter()
                try:
                    out = subprocess.run([dcad, "solve", fh.name, "--backend", backend, "--json", "--with", "none"], capture_output=True, text=True,
                                         timeout=300 if backend == "fast" else 3600, preexec_fn=limit_memory)
                except subprocess.TimeoutExpired:
                    print(f"| {n + 1} | {family} | {backend} | > 300 | | | | timeout |")
                    continue
                dt = time.perf_counter() - t0
                if out.returncode != 0:
                    print(f"| {n + 1} | {family} | {backend} | {dt:.2f} | exit {out.returncode}: {out.stderr.strip()[:60]} | | | |")
                    continue
                r = json.loads(out.stdout)
                if backend == "certified" and r["certified"]:
                    exact = r["dims"]
                yard = want or exact
                right = "by hand" if want and r["dims"] == want else "as certified" if yard and r["dims"] == yard else "WRONG" if yard else "?"
                dims = r["dims"] if len(r["dims"]) <= 4 else r["dims"][:4] + ["..."]
                print(f"| {n + 1} | {family} | {backend} | {dt:.2f} | {dims} | {r.get('index')} | {r['certified']} | {right} |")
                sys.stdout.flush()


if __name__ == "__main__":
    main()
