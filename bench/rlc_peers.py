#!/usr/bin/env python3
"""RLC decks: dcad simulate against ngspice, both against closed forms where they exist (issue 12).

1. Series RLC from rest (cases/rlc-series.cir) and RL step (cases/rl-step.cir): trajectory error
   max |x − exact| / max |exact| of the inductor current on the output grid, and wall time (best of
   3), dcad at several steps, ngspice at several reltol (tmax = the output step).
2. Random RLC decks with sources, capacitor loops and inductor cutsets: ngspice's answer against
   dcad's; where ngspice fails (timestep too small, singular matrix) the row says so and dcad's
   answer stands alone.
    python3 bench/rlc_peers.py DCAD_BINARY CASES_DIR OUT_CSV
"""
import math
import os
import random
import subprocess
import sys
import tempfile

from trajectory import best_of  # bench/ is on the path when run as a script


def dcad_run(dcad, deck, tstop, step, var, tmp):
    csv = os.path.join(tmp, "d.csv")
    subprocess.run([dcad, "simulate", deck, "--tstop", repr(tstop), "--step", repr(step), "--csv", csv],
                   check=True, stderr=subprocess.DEVNULL)
    with open(csv) as f:
        head = f.readline().strip().split(",")
        k = head.index(var)
        return [(float(r[0]), float(r[k])) for r in (line.split(",") for line in f)]


def ngspice_run(lines, tstop, step, reltol, probe, tmp, uic=True):
    data, deck, log = (os.path.join(tmp, x) for x in ("ng.txt", "ng.cir", "ng.log"))
    if os.path.exists(data):
        os.remove(data)
    with open(deck, "w") as f:
        f.write("".join(l for l in lines if not l.lower().startswith((".tran", ".end"))))
        f.write(f".options reltol={reltol} abstol=1e-15\n.tran {step} {tstop} 0 {step}{' uic' if uic else ''}\n.control\nset wr_singlescale\nrun\n"
                f"linearize {probe}\nwrdata {data} {probe}\n.endc\n.end\n")
    with open(log, "w") as lf:
        subprocess.run(["ngspice", "-b", deck], stdout=lf, stderr=subprocess.STDOUT)
    text = open(log).read().lower()
    trouble = "; ".join(w for w, key in (("timestep too small", "timestep too small"), ("singular matrix", "singular matrix"),
                                         ("gmin stepping failed", "gmin stepping failed"), ("source stepping failed", "source stepping failed"))
                        if key in text)
    if not os.path.exists(data):
        return None, trouble or "no output"
    rows = []
    with open(data) as f:
        for line in f:
            p = line.split()
            if len(p) >= 2:
                rows.append((float(p[0]), float(p[1])))
    return rows, trouble


def err(rows, exact):
    ref = max(abs(exact(t)) for t, _ in rows) or 1.0
    return max(abs(x - exact(t)) for t, x in rows) / ref


def against(rows, other):
    ref = max(abs(x) for _, x in other) or 1.0
    return max(abs(a[1] - b[1]) for a, b in zip(rows, other)) / ref


def closed_forms(cases):
    R, L, C, V = 10, 1e-3, 1e-6, 1.0
    a, w0 = R / (2 * L), 1 / math.sqrt(L * C)
    wd = math.sqrt(w0 * w0 - a * a)
    yield "rlc-series", os.path.join(cases, "rlc-series.cir"), 1e-3, lambda t: V / (L * wd) * math.exp(-a * t) * math.sin(wd * t)
    yield "rl-step", os.path.join(cases, "rl-step.cir"), 5e-4, lambda t: 5.0 / 100 * (1 - math.exp(-100 * t / 10e-3))


# Decks where ngspice's own flow (DC operating point first, no `uic`) meets a loop of a voltage
# source and an inductor (singular at DC) or a node cut off by current sources and capacitors
# (no DC path): dcad needs no operating point, the CAD states the constraint and integrates.
HARD = [
    ("v-l-loop", "voltage source across an inductor (a V-L loop: singular at DC)\n"
                 "V1 a 0 SIN(0 1 1k)\nL1 a 0 1m\nR1 a b 10\nC1 b 0 1u\n.end\n", "L1", True),
    ("i-c-cutset", "current sources into a capacitor-only node (no DC path)\n"
                   "I1 0 a PULSE(0 1m 0 1u 1u 100u 200u)\nC1 a 0 1u\nC2 a b 1u\nL1 b 0 1m\n.end\n", "L1", True),
    ("cv-loop-pulse", "pulse source across two capacitors in parallel (a CV loop with corners)\n"
                      "V1 a 0 PULSE(0 1 0 1u 1u 100u 200u)\nC1 a 0 1u\nC2 a 0 2u\nR1 a b 10\nL1 b 0 1m\n.end\n", "L1", True),
]


def random_deck(rng, k):
    """A ladder of RLC sections driven by a SIN or PULSE source, with a capacitor across the source
    (a CV loop) or a current source into an inductor pair (an LI cutset)."""
    n = rng.randint(2, 5)
    lines = [f"random RLC {k}\n"]
    if rng.random() < 0.5:
        lines.append(f"V1 n0 0 SIN(0 {rng.choice([1, 5])} {rng.choice(['1k', '10k'])})\n")
        lines.append(f"Cs n0 0 {rng.choice(['1n', '10n'])}\n")  # a capacitor across a voltage source: CV loop
        kind = "cv-loop"
    else:
        lines.append(f"I1 0 n0 PULSE(0 1m 0 1u 1u 100u 200u)\n")
        lines.append(f"Lx n0 0 {rng.choice(['1m', '2m'])}\nLy n0 n1 {rng.choice(['1m', '3m'])}\n")  # LI cutset {I1, Lx, Ly}
        kind = "li-cutset"
    start = 1 if kind == "li-cutset" else 0
    for i in range(start, n + 1):
        lines.append(f"R{i} n{i} n{i+1} {rng.choice(['1', '10', '100'])}\n")
        lines.append(f"L{i} n{i+1} n{i+2} {rng.choice(['100u', '1m'])}\n")
        lines.append(f"C{i} n{i+2} 0 {rng.choice(['100n', '1u'])}\n")
    lines.append(".end\n")
    return kind, lines, "L1" if kind == "cv-loop" else "L2"


def main():
    dcad, cases, out = sys.argv[1:4]
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, deck, tstop, exact in closed_forms(cases):
            for step in (tstop / 100, tstop / 1000):
                secs, r = best_of(3, lambda: dcad_run(dcad, deck, tstop, step, "v_L1", tmp))
                rows.append(("closed-form", name, "dcad", f"step={step:g}", err(r, exact), secs, ""))
            lines = open(deck).readlines()
            for reltol in (1e-3, 1e-6, 1e-9):
                secs, (r, why) = best_of(3, lambda: ngspice_run(lines, tstop, tstop / 1000, reltol, "i(l1)", tmp))
                rows.append(("closed-form", name, "ngspice", f"reltol={reltol:g}", err(r, exact) if r else float("nan"), secs, why))
        rng = random.Random(12)
        for k in range(12):
            kind, lines, ind = random_deck(rng, k)
            deck = os.path.join(tmp, f"r{k}.cir")
            open(deck, "w").writelines(lines)
            try:
                secs, d = best_of(1, lambda: dcad_run(dcad, deck, 1e-3, 1e-6, "v_" + ind, tmp))
            except subprocess.CalledProcessError as e:
                rows.append(("random", f"{kind}-{k}", "dcad", "step=1e-06", float("nan"), 0.0, f"dcad exit {e.returncode}"))
                continue
            rows.append(("random", f"{kind}-{k}", "dcad", "step=1e-06", 0.0, secs, ""))
            nsecs, (r, why) = best_of(1, lambda: ngspice_run(lines, 1e-3, 1e-6, 1e-6, f"i({ind.lower()})", tmp))
            rows.append(("random", f"{kind}-{k}", "ngspice", "reltol=1e-06", against(r, d) if r else float("nan"), nsecs, why))
        for name, text, ind, _ in HARD:
            deck = os.path.join(tmp, f"{name}.cir")
            open(deck, "w").write(text)
            lines = text.splitlines(keepends=True)
            secs, d = best_of(1, lambda: dcad_run(dcad, deck, 1e-3, 1e-6, "v_" + ind, tmp))
            rows.append(("hard", name, "dcad", "step=1e-06", 0.0, secs, ""))
            for uic in (False, True):
                nsecs, (r, why) = best_of(1, lambda: ngspice_run(lines, 1e-3, 1e-6, 1e-6, f"i({ind.lower()})", tmp, uic))
                rows.append(("hard", name, "ngspice", "reltol=1e-06" + (" uic" if uic else " (operating point)"),
                             against(r, d) if r else float("nan"), nsecs, why))
    with open(out, "w") as f:
        f.write("family,deck,tool,setting,error,seconds,failure\n")
        for r in rows:
            f.write(",".join(str(x) for x in r) + "\n")
    for r in rows:
        print(*r, sep="\t")


if __name__ == "__main__":
    main()
