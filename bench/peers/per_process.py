"""Reference against sympy as a user's CI runs them (issue 14): one process per case, and one
process for the whole corpus; the same instances as the sweep, the same CAD, the same answers.

For every family/parameter of instances.jsonl (the sweep's exact instances, up to --per instances
each, N <= --max-n) this writes a dcad case file (dirac: presymplectic ω, energy: Hessian) and times
  dcad-per-process    build/dcad solve --backend reference --json --with none FILE     (one process per case)
  dcad-one-process    build/dcad solve --backend reference --jsonl --with none FILES…  (all cases, one process)
  sympy-per-process   /usr/bin/python3 cad_peers.py --one FILE                         (one process per case: start, import, CAD)
  sympy-in-process    cad_peers.cad(Sympy, …) in this interpreter                      (the CAD alone)
and checks that dcad's dims and solution rank are sympy's.  Wall-clock seconds per case, best of
--reps runs.  CSV on stdout: family,param,n,cases,dcad_per_process,dcad_one_process,sympy_per_process,sympy_in_process.

Run: /usr/bin/python3 bench/peers/per_process.py build/dcad build/bench_instances.jsonl [--per 2] [--max-n 21] [--reps 3]
"""
import json
import os
import subprocess
import sys
import tempfile
import time
from collections import defaultdict

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cad_peers  # noqa: E402  (the sympy CAD of the sweep's peers)


def best(reps, f):
    t = float("inf")
    for _ in range(reps):
        t0 = time.perf_counter()
        f()
        t = min(t, time.perf_counter() - t0)
    return t


def main():
    args = sys.argv[1:]
    if len(args) < 2:
        sys.exit(__doc__)
    dcad, instances = args[0], args[1]
    opt = {"--per": 2, "--max-n": 21, "--reps": 3}
    for k in opt:
        if k in args:
            opt[k] = int(args[args.index(k) + 1])
    groups = defaultdict(list)
    with open(instances) as f:
        for line in f:
            if line.strip():
                inst = json.loads(line)
                key = (inst["family"], inst["param"])
                if len(inst["omega"]) <= opt["--max-n"] and len(groups[key]) < opt["--per"]:
                    groups[key].append(inst)
    tmp = tempfile.mkdtemp(prefix="dcad_per_process_")
    peers = os.path.join(os.path.dirname(os.path.abspath(__file__)), "cad_peers.py")
    print("family,param,n,cases,dcad_per_process,dcad_one_process,sympy_per_process,sympy_in_process")
    for (family, param), insts in sorted(groups.items(), key=lambda kv: (kv[0][0], float(kv[0][1]))):
        files = []
        for i, inst in enumerate(insts):
            n = len(inst["omega"])
            case = {"dcad": 1, "name": f"{family}-{param}-{i}", "variables": [f"x{j + 1}" for j in range(n)],
                    "dirac": {"presymplectic": inst["omega"]}, "energy": {"hessian": inst["hessian"]}}
            path = os.path.join(tmp, f"{family}-{param}-{i}.json")
            with open(path, "w") as out:
                json.dump(case, out)
            files.append(path)
            got = json.loads(subprocess.run([dcad, "solve", "--backend", "reference", "--json", "--with", "none", path],
                                            check=True, capture_output=True, text=True).stdout)
            if got["dims"] != inst["dims"] or got["solution_rank"] != inst["solution_rank"]:
                sys.exit(f"{path}: dcad {got['dims']}/{got['solution_rank']} differs from the sweep's reference "
                         f"{inst['dims']}/{inst['solution_rank']}")
        reps = opt["--reps"]
        per = sum(best(reps, lambda p=p: subprocess.run([dcad, "solve", "--backend", "reference", "--json", "--with", "none", p],
                                                           check=True, capture_output=True)) for p in files) / len(files)
        one = best(reps, lambda: subprocess.run([dcad, "solve", "--backend", "reference", "--jsonl", "--with", "none"] + files,
                                                check=True, capture_output=True)) / len(files)
        sym_per = sum(best(reps, lambda p=p: subprocess.run(["/usr/bin/python3", peers, "--one", p], check=True,
                                                              capture_output=True)) for p in files) / len(files)
        sym_in = 0.0
        for inst in insts:
            omega, hessian = cad_peers.Sympy.convert(inst["omega"]), cad_peers.Sympy.convert(inst["hessian"])
            dims, srank, _ = cad_peers.cad(cad_peers.Sympy, omega, hessian)
            if dims != inst["dims"] or srank != inst["solution_rank"]:
                sys.exit(f"sympy disagrees with the reference on {family}({param})")
            sym_in += best(reps, lambda: cad_peers.cad(cad_peers.Sympy, omega, hessian))
        sym_in /= len(insts)
        print(f"{family},{param:g},{len(insts[0]['omega'])},{len(insts)},{per:.6g},{one:.6g},{sym_per:.6g},{sym_in:.6g}", flush=True)


if __name__ == "__main__":
    main()
