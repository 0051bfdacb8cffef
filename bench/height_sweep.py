#!/usr/bin/python3
"""fast's separation hypothesis on integer data of moderate height (the soundness sweep of stop 64).

fast's zero tests in double are certain only if exact nonzeros are never within a few rounding bounds of 0
(fast/include/dcad/fast/rank.hpp).  Integer matrices break that without any rounding of the input: for
E = U^T D U with U unimodular (a product of integer shears) and D = diag of small integers, det E = det D is
small while the entries reach 10^6-10^7, so the smallest singular value is about det / (sigma_1 sigma_2) ~ 1e-10
(Cauchy-Binet), below what double resolves.  Each instance is an invertible E, so by hand every answer is the
regular one: the Lagrangian L = 1/2 v^T E v has dims [9, 6] and solution rank 0; the implicit E v + x = 0 and the
DAE E x' = x have dims [3].  For each form this prints how often fast's own decisions are wrong (its answer differs
from the reference's), how often `--backend fast` says certified, and how often it says certified while wrong —
which must be 0 (fast::solve confirms a certain answer by the certified tier, reference/fast_backend/src/solve.cpp).

usage: bench/height_sweep.py DCAD [INSTANCES [SEED]]    (writes the cases under /tmp)"""
import json, os, random, subprocess, sys, tempfile, time


def unimodular_congruent(rng, n=3):
    u = [[1 if i == j else 0 for j in range(n)] for i in range(n)]
    for _ in range(rng.randint(3, 7)):
        i, j = rng.sample(range(n), 2)
        k = rng.randint(-30, 30)
        for c in range(n):
            u[i][c] += k * u[j][c]
    d = [rng.choice([1, -1, 2, -17, 3]) for _ in range(n)]
    return [[sum(u[k][i] * d[k] * u[k][j] for k in range(n)) for j in range(n)] for i in range(n)]


def cases(m):
    x, v = ["x", "y", "z"], ["v_x", "v_y", "v_z"]
    lag = " + ".join(f"({m[i][j]})*{v[i]}*{v[j]}/2" for i in range(3) for j in range(3))
    eqs = [" + ".join(f"({m[i][j]})*{v[j]}" for j in range(3)) + f" + {x[i]}" for i in range(3)]
    eye = [["1" if i == j else "0" for j in range(3)] for i in range(3)]
    return {
        "lagrangian": {"dcad": 1, "name": "h", "lagrangian": {"coordinates": x, "L": lag}},
        "implicit": {"dcad": 1, "name": "h", "implicit": {"coordinates": x, "equations": eqs}},
        "dae": {"dcad": 1, "name": "h", "variables": x,
                "dae": {"E": [[str(a) for a in r] for r in m], "A": eye, "f": ["0", "0", "0"]}},
    }


def solve(dcad, path, backend):
    t = time.perf_counter()
    out = subprocess.run([dcad, "solve", path, "--backend", backend, "--json"], capture_output=True, text=True)
    return json.loads(out.stdout), time.perf_counter() - t


def main():
    dcad = sys.argv[1]
    count = int(sys.argv[2]) if len(sys.argv) > 2 else 100
    rng = random.Random(int(sys.argv[3]) if len(sys.argv) > 3 else 1)
    forms = ["lagrangian", "implicit", "dae"]
    tally = {f: {"wrong": 0, "certified": 0, "certified_wrong": 0, "confirmed": 0, "fast_s": 0.0, "ref_s": 0.0}
             for f in forms}
    tmp = tempfile.mkdtemp(prefix="dcad_height_")
    for _ in range(count):
        m = unimodular_congruent(rng)
        for form, case in cases(m).items():
            path = os.path.join(tmp, form + ".json")
            with open(path, "w") as f:
                json.dump(case, f)
            fast, tf = solve(dcad, path, "fast")
            ref, tr = solve(dcad, path, "reference")
            t = tally[form]
            wrong = fast["dims"] != ref["dims"] or fast["solution_rank"] != ref["solution_rank"]
            t["wrong"] += wrong
            t["certified"] += fast["certified"]
            t["certified_wrong"] += fast["certified"] and wrong
            t["confirmed"] += fast.get("decisions", {}).get("exact_verification", 0)
            t["fast_s"] += tf
            t["ref_s"] += tr
    print(f"{count} instances per form (E = U^T D U, U unimodular; seed {sys.argv[3] if len(sys.argv) > 3 else 1})")
    print("form        fast's own answer wrong  fast certified  of them confirmed  certified AND wrong  "
          "fast s  reference s")
    for form in forms:
        t = tally[form]
        print(f"{form:<11} {t['wrong']:>23}  {t['certified']:>14}  {t['confirmed']:>17}  {t['certified_wrong']:>19}  "
              f"{t['fast_s']:>6.2f}  {t['ref_s']:>11.2f}")
    return 1 if any(tally[f]["certified_wrong"] for f in forms) else 0


if __name__ == "__main__":
    sys.exit(main())
