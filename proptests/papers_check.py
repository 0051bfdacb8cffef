#!/usr/bin/env python3
"""The papers' traceability table (issue 46): proptests/papers.tsv has one row per statement of CEF, YM and V as
../shared/PAPER-ITEMS.md numbers them (1-110 CEF, Y1-Y25 YM, V1-V10 V, N1-N6 found later), tab-separated under
the header `id status reference fast tests`.  Fails when an id is missing, doubled or unknown, a status is not
covered / partial / missing / one-sided: REASON, a covered row names no test or not both twins' implementations,
or a row names a test that ctest does not have (the names come from `ctest -N` on this build).

Usage: papers_check.py SOURCE_DIR BUILD_DIR CTEST
"""
import re
import subprocess
import sys

IDS = [str(k) for k in range(1, 111)] + ["Y%d" % k for k in range(1, 26)] + ["V%d" % k for k in range(1, 11)] + \
      ["N%d" % k for k in range(1, 7)]
HEADER = ["id", "status", "reference", "fast", "tests"]


def main():
    source, build, ctest = sys.argv[1:4]
    listed = subprocess.run([ctest, "--test-dir", build, "-N"], capture_output=True, text=True, check=True).stdout
    names = set(re.findall(r"^\s*Test\s+#\d+: (\S+)", listed, re.M))
    if len(names) < 100:
        print(f"expected the build's ctest names from `ctest -N`, found {len(names)}")
        return 1
    path = source + "/proptests/papers.tsv"
    rows, bad = {}, []
    with open(path, encoding="utf-8") as f:
        lines = f.read().split("\n")
    if lines[0].split("\t") != HEADER:
        bad.append(f"{path}:1: expected the header {' '.join(HEADER)} (tab-separated), found {lines[0]!r}")
    for k, line in enumerate(lines[1:], 2):
        if not line.strip():
            continue
        cells = line.split("\t")
        if len(cells) != 5:
            bad.append(f"{path}:{k}: expected 5 tab-separated cells, found {len(cells)}")
            continue
        ident, status, ref, fast, tests = (c.strip() for c in cells)
        if ident in rows:
            bad.append(f"{path}:{k}: id {ident} twice (first at line {rows[ident]})")
        rows[ident] = k
        if ident not in IDS:
            bad.append(f"{path}:{k}: expected an id of PAPER-ITEMS.md, found {ident!r}")
        if status not in ("covered", "partial", "missing") and not re.match(r"one-sided: \S", status):
            bad.append(f"{path}:{k}: {ident}: expected covered, partial, missing or 'one-sided: REASON', found {status!r}")
        named = [t.strip() for t in tests.split(",") if t.strip() and t.strip() != "-"]
        for t in named:
            if t not in names:
                bad.append(f"{path}:{k}: {ident}: expected a ctest name, found {t!r} (no such test in this build)")
        if status == "covered" or status.startswith("one-sided"):
            if not named:
                bad.append(f"{path}:{k}: {ident}: {status.split(':')[0]} names no test that holds it")
            if ref == "-" and fast == "-":
                bad.append(f"{path}:{k}: {ident}: {status.split(':')[0]} names no implementation")
            elif status == "covered" and (ref == "-" or fast == "-"):
                bad.append(f"{path}:{k}: {ident}: covered names one twin only (both twins, or one-sided: REASON)")
    for ident in IDS:
        if ident not in rows:
            bad.append(f"{path}: expected a row for id {ident}, found none")
    for b in bad:
        print(b)
    status = {}
    for line in lines[1:]:
        cells = line.split("\t")
        if len(cells) == 5:
            s = cells[1].split(":")[0]
            status[s] = status.get(s, 0) + 1
    print("papers.tsv: " + ", ".join(f"{n} {s}" for s, n in sorted(status.items())) + f"; {len(bad)} findings")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
