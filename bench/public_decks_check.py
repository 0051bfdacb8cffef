#!/usr/bin/env python3
"""The public decks of bench/public_decks.tsv through ngspice and back through `dcad check` (issue 45).

For every deck meant to run that dcad accepts, has a .tran card and no .step or .control: ngspice -b -r
writes its transient (raw), and `dcad check RAW DECK --dialect D --json` compares it with the exact flow of
the deck at ngspice's own time points (default --rtol 1e-3).  A disagreement is a finding about one of the
two: where ngspice converges to dcad's value with tight tolerances (.options reltol=1e-7, TMAX = TSTEP/100)
it was ngspice's default accuracy.  Needs ngspice on PATH and the corpus (see public_decks.py):

    /usr/bin/python3 bench/public_decks_check.py build/dcad CORPUS [--out bench/results/public_decks_check.md]
"""
import csv
import json
import os
import re
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import public_decks as pd  # noqa: E402


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    dcad, corpus = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    out = sys.argv[sys.argv.index("--out") + 1] if "--out" in sys.argv else os.path.join(os.path.dirname(__file__), "results", "public_decks_check.md")
    rows = list(csv.DictReader(open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "public_decks.tsv")), delimiter="\t"))
    results = []  # (source, path, verdict, certified, detail)
    t_all = time.monotonic()
    work = tempfile.mkdtemp(prefix="dcad_decks_check_")
    for n, r in enumerate(rows):
        deck = os.path.join(corpus, r["source"], r["path"])
        if pd.meant_to_fail(r["path"]) or not os.path.isfile(deck):
            continue
        text = open(deck, errors="replace").read().lower()
        if not re.search(r"^\s*\.tran", text, re.M) or ".step" in text or ".control" in text:
            continue
        where, name, dialect = os.path.dirname(deck), os.path.basename(deck), pd.dialect(r["source"], deck)
        if subprocess.run([dcad, "solve", "--with", "none", "--dialect", dialect, name], cwd=where, capture_output=True, timeout=60).returncode != 0:
            continue
        raw = os.path.join(work, "%d.raw" % n)
        try:
            subprocess.run(["ngspice", "-b", "-r", raw, name], cwd=where, capture_output=True, timeout=30)
        except subprocess.TimeoutExpired:
            results.append((r["source"], r["path"], "ngspice timeout", "", ""))
            continue
        if not os.path.isfile(raw) or os.path.getsize(raw) == 0:
            results.append((r["source"], r["path"], "no ngspice output", "", ""))
            continue
        try:
            c = subprocess.run([dcad, "check", raw, name, "--dialect", dialect, "--json"], cwd=where, capture_output=True, timeout=120)
        except subprocess.TimeoutExpired:
            results.append((r["source"], r["path"], "dcad timeout", "", ""))
            continue
        os.remove(raw)
        if c.returncode not in (0, 3):
            last = (c.stderr.decode(errors="replace").strip().splitlines() or [""])[-1]
            results.append((r["source"], r["path"], "exit %d" % c.returncode, "", last[:160]))
            continue
        j = json.loads(c.stdout)
        bad = [v for v in j["vectors"] if not v.get("agree", True)]
        decided = all(v.get("decided", True) for v in bad)
        verdict = "agrees" if j["agree"] else "disagrees" if decided else "undecided"
        worst = max(bad, key=lambda v: (v.get("max_error") or 0) / max(v.get("scale") or 1e-300, 1e-300), default=None)
        detail = "" if worst is None else "%s: %.3g of %.3g at t = %.6g" % (worst["name"], worst.get("max_error") or 0, worst.get("scale") or 0, worst.get("at") or 0)
        results.append((r["source"], r["path"], verdict, "yes" if j.get("certified") else "no", detail))
    seconds = time.monotonic() - t_all
    counts = {}
    for res in results:
        counts[res[2]] = counts.get(res[2], 0) + 1
    with open(out, "w") as f:
        f.write("# Public decks: ngspice's transient against dcad's exact flow (`dcad check`)\n\n")
        f.write("`/usr/bin/python3 bench/public_decks_check.py build/dcad CORPUS` — %d decks, %.0f s; ngspice-39 at its default\n"
                "tolerances, `dcad check` at its default --rtol 1e-3 of each vector's largest |exact|.\n\n" % (len(results), seconds))
        f.write("| verdict | decks |\n|---|---|\n")
        for k, v in sorted(counts.items(), key=lambda kv: -kv[1]):
            f.write("| %s | %d |\n" % (k, v))
        f.write("\n| source | deck | verdict | certified | worst vector |\n|---|---|---|---|---|\n")
        for res in results:
            if res[2] != "agrees":
                f.write("| %s | `%s` | %s | %s | %s |\n" % res)
    print("%d decks: %s; table in %s" % (len(results), ", ".join("%s %d" % kv for kv in sorted(counts.items())), out))


if __name__ == "__main__":
    main()
