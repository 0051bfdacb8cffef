#!/usr/bin/env python3
"""The published DAE benchmark set (cases/published/, issues 49 and 51) on every backend, one run each.

For each problem: `dcad solve --backend B --json` on reference, fast and certified — exit code, tower, index
against the source's published index and the hand derivation (`expect`), certified, seconds — and
`dcad simulate` over the published interval with the output grid every tenth of it, its last row against the
source's published solution (largest error relative to max(1, |published|)).  A run that takes longer than
TIMEOUT seconds (default 120) is stopped and reported as such.

    cmake -S . -B build && cmake --build build -j2 --target dcad
    /usr/bin/python3 bench/published_daes.py build/dcad          (TIMEOUT=300 for longer runs)
Writes bench/results/published_daes.md.
"""
import json
import os
import subprocess
import sys
import time
from fractions import Fraction
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
TIMEOUT = float(os.environ.get("TIMEOUT", "120"))


def run(args):
    t0 = time.monotonic()
    try:
        p = subprocess.run(args, capture_output=True, text=True, timeout=TIMEOUT)
        return p.returncode, p.stdout, p.stderr, time.monotonic() - t0
    except subprocess.TimeoutExpired:
        return None, "", "", time.monotonic() - t0


def solve_cell(dcad, case, backend, want):
    rc, out, err, secs = run([dcad, "solve", str(case), "--backend", backend, "--json"])
    if rc is None:
        return f"> {TIMEOUT:.0f} s (stopped)"
    if rc != 0:
        return f"exit {rc} in {secs:.2f} s: {err.strip().splitlines()[-1][:160] if err.strip() else ''}"
    d = json.loads(out)
    same = d.get("dims") == want.get("dims") and d.get("index") == want.get("index")
    return (f"{d.get('dims')} index {d.get('index')}{'' if same else ' (DIFFERS)'}, "
            f"certified {str(d.get('certified')).lower()}, {secs:.2f} s")


def simulate_cell(dcad, case, pub):
    if "interval" not in pub or "solution" not in pub:
        return "no published solution"
    t0, t1 = (Fraction(x) for x in pub["interval"])
    step = (t1 - t0) / 10
    rc, out, err, secs = run([dcad, "simulate", str(case), "--tstop", str(float(t1)), "--step", str(float(step))])
    if rc is None:
        return f"> {TIMEOUT:.0f} s (stopped)"
    if rc != 0:
        last = err.strip().splitlines()[-1] if err.strip() else ""
        return f"exit {rc} after {secs:.1f} s: {last[:200]}"
    rows = [r for r in out.strip().splitlines() if r and not r.startswith("t,")]
    header = out.strip().splitlines()[0].split(",")
    last = dict(zip(header, (float(x) for x in rows[-1].split(","))))
    if abs(last["t"] - float(t1)) > 1e-9 * max(1.0, abs(float(t1))):
        return f"stopped at t = {last['t']} ({secs:.1f} s)"
    worst = max(abs(last[k] - float(Fraction(v))) / max(1.0, abs(float(Fraction(v))))
                for k, v in pub["solution"]["values"].items())
    return f"largest error {worst:.1e} at t = {float(t1)} in {secs:.1f} s"


def main():
    dcad = str(Path(sys.argv[1]).resolve()) if len(sys.argv) > 1 else str(ROOT / "build" / "dcad")
    os.chdir(ROOT)  # cases by their paths in the repository, as messages name them
    lines = ["# The published DAE benchmark set (cases/published/)", "",
             f"`/usr/bin/python3 bench/published_daes.py {sys.argv[1] if len(sys.argv) > 1 else 'build/dcad'}` — one run each, stopped after {TIMEOUT:.0f} s.", "",
             "| problem | variables | published index (source) | reference | fast | certified | simulate over the published interval |",
             "|---|---|---|---|---|---|---|"]
    for case in sorted((ROOT / "cases" / "published").glob("*.json")):
        c = json.loads(case.read_text())
        pub, want = c["published"], c["expect"]
        form = c.get("implicit") or c.get("lagrangian") or {}
        n = len(form.get("coordinates", c.get("variables", [])))
        case = case.relative_to(ROOT)
        cells = [solve_cell(dcad, case, b, want) for b in ("reference", "fast", "certified")]
        sim = simulate_cell(dcad, case, pub)
        src = pub["source"].split(",")[0]
        lines.append(f"| {c['name']} | {n} | {pub.get('index')} ({src}) | " + " | ".join(cells) + f" | {sim} |")
        print(lines[-1], flush=True)
    out = ROOT / "bench" / "results" / "published_daes.md"
    out.write_text("\n".join(lines) + "\n")
    print(f"table in {out}")


if __name__ == "__main__":
    main()
