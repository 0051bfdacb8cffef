#!/usr/bin/python3
"""The verdict table from bench/corpus_verdicts.sh's files in OUT (markdown on stdout), with dcad's verdicts held to oracle.py's."""
import json, os, re, sys

OUT = sys.argv[1]
DECKS = ["rc-pulse", "cap-triangle-inductor-cutset", "lc-tank-1000-periods", "lc-tank-10000-periods",
         "mixed-scale-rlc", "pwl-rlc", "transformer-k1"]


def read(p, default=""):
    try:
        return open(p, errors="replace").read().strip()
    except OSError:
        return default


def points(p, sim):
    if sim == "ngspice":
        try:
            head = open(p + ".raw", "rb").read(4000).decode("latin-1")
        except OSError:
            return "no raw file"
        m = re.search(r"No\. Points:\s*(\d+)", head)
        return m.group(1) if m else "?"
    n = 0
    for line in open(p + ".txt", errors="replace"):
        if re.match(r"\s*[-+0-9.]", line):
            n += 1
    return str(n)


def oracle(p):
    vec = {}
    for line in read(p + ".oracle").splitlines():
        m = re.match(r"(agrees|DISAGREES)\s+(\S+)\s+largest error (\S+) of (\S+) at t = (\S+)", line)
        if m:
            vec[m.group(2).lower()] = (m.group(1) == "agrees", float(m.group(3)), float(m.group(4)), float(m.group(5)))
    return vec


rows, notes = [], []
print("| deck | sim | setting | simulator (rc, points, s) | check exit | verdict | certified | worst vector: error (of scale) at t | check s | oracle exit, its error on that vector | oracle = dcad |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
for d in DECKS:
    for sim in ("ngspice", "gnucap"):
        for st in ("default", "tight", "tight+stripped"):
            p = os.path.join(OUT, "%s.%s.%s" % (d, sim, st))
            if not os.path.exists(p + ".simrc"):
                continue
            src = read(p + ".simrc")
            simt = read(p + ".simtime").splitlines()[-1:] or ["?"]
            if src == "124":
                print("| %s | %s | %s | timeout (120 s) | – | simulator did not finish | – | – | – | – | – |" % (d, sim, st))
                continue
            simcol = "%s, %s pts, %s" % (src, points(p, sim), simt[0])
            if "points" in (j0 := (json.loads(read(p + ".json")) if read(p + ".json").startswith("{") else {})):
                if str(j0["points"]) != points(p, sim):
                    simcol += " (**dcad read %s**)" % j0["points"]
            log = read(p + ".simlog").lower()
            if "too small" in log:
                simcol += ", *timestep too small*"
            crc = read(p + ".checkrc")
            ct = read(p + ".checktime").splitlines()[-1:] or ["?"]
            orc = read(p + ".oraclerc")
            ov = oracle(p)
            try:
                j = json.loads(read(p + ".json"))
            except ValueError:
                j = None
            if j is None:
                err = read(p + ".checkerr").splitlines()
                msg = (err[0] if err else "?")[:90].replace("|", "/")
                same = "yes" if (crc == "1") == (orc == "1") else "**NO**"
                print("| %s | %s | %s | %s | %s | bad input: %s | – | – | %s | %s | %s |" % (d, sim, st, simcol, crc, msg, ct[0], orc, same))
                continue
            vecs = j["vectors"]
            undecided = [v["name"] for v in vecs if not v.get("decided", True)]
            bad = [v["name"] for v in vecs if not v["agree"] and v.get("decided", True)]
            verdict = "agrees" if j["agree"] else ("DISAGREES " + ",".join(bad) if bad else "") + (" UNDECIDED " + ",".join(undecided) if undecided else "")
            rel = lambda v: v["max_error"] / v["scale"] if v["scale"] else (float("inf") if v["max_error"] else 0)
            w = max(vecs, key=rel)
            worst = "%s: %.3g (%.3g of %.3g) at %.6g" % (w["name"], w["max_error"], rel(w), w["scale"], w["at"])
            cert = "yes" if j["certified"] else "no (%s)" % j.get("certified_reason", "")[:60]
            o = ov.get(w["name"].lower())
            ocol = "%s, %s" % (orc, "%.3g of %.3g" % (o[1], o[2]) if o else "(vector not in oracle)")
            # the oracle's truth against dcad's verdict, vector by vector and overall
            mism = []
            for v in vecs:
                ovv = ov.get(v["name"].lower())
                if ovv is None:
                    continue
                if v.get("decided", True) and v["agree"] != ovv[0]:
                    mism.append("%s: dcad %s, oracle %s" % (v["name"], "agrees" if v["agree"] else "DISAGREES", "agrees" if ovv[0] else "DISAGREES"))
                if ovv[1] > 0 and abs(v["max_error"] - ovv[1]) > 1e-6 * max(ovv[2], v["scale"]) + 1e-3 * ovv[1]:
                    notes.append("%s %s %s %s: max error dcad %.6g at %.6g, oracle %.6g at %.6g" % (d, sim, st, v["name"], v["max_error"], v["at"], ovv[1], ovv[3]))
            overall = (crc == "0") == (orc == "0")
            same = "yes" if overall and not mism else "**NO** " + "; ".join(mism)
            if undecided:
                same += " (dcad undecided on %s)" % ",".join(undecided)
            print("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (d, sim, st, simcol, crc, verdict, cert, worst, ct[0], ocol, same))
if notes:
    print("\nWhere dcad's largest error differs from the oracle's (beyond 1e-6 of scale):\n")
    for n in notes:
        print("- " + n)
