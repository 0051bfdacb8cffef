#!/usr/bin/env python3
"""The copied-code ratchet (issue 47: "a check for copied code on each change"): no run of RUN or more code lines
of the library (reference/, fast/, cli/) stands again, to the letter, elsewhere in it — save between the pairs of
files listed in copies.txt, at no more shared lines than listed.  A pair whose copy has shrunk must be lowered
(or leave the list when it is gone), so the list only shrinks.  A new copy fails: make one function serve both.

Lines are compared as written, comments dropped and white space ignored; #include lines and lines without a
letter or digit (braces, `};`) do not count, so a run is RUN lines of code.

Usage: copies.py ROOT [--list]   (--list prints today's pairs in the list's format)
"""
import collections
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from function_lengths import DIRS, blank, ratchet, read_listing  # noqa: E402

RUN = 6


def code_lines(path):
    """(line number, text) of the lines that count: comments dropped, white space collapsed."""
    text = blank(open(path, encoding="utf-8").read(), literals=False)
    out = []
    for k, line in enumerate(text.split("\n"), 1):
        t = " ".join(line.split())
        if t and not t.startswith("#include") and any(ch.isalnum() for ch in t):
            out.append((k, t))
    return out


def pairs(root):
    """{(file a, file b): shared lines of a} over every run of RUN lines standing in both (a <= b)."""
    files = {}
    for d in DIRS:
        for dp, _, fns in os.walk(os.path.join(root, d)):
            for f in sorted(fns):
                if f.endswith((".cpp", ".hpp")):
                    p = os.path.join(dp, f)
                    files[os.path.relpath(p, root)] = code_lines(p)
    where = collections.defaultdict(list)  # a run's text -> (file, index of its first line)
    for rel, lines in files.items():
        for i in range(len(lines) - RUN + 1):
            where["\n".join(t for _, t in lines[i:i + RUN])].append((rel, i))
    shared = collections.defaultdict(set)  # (a, b) -> indices of a's lines in a run that b has too
    for places in where.values():
        if len(places) < 2:
            continue
        for x in range(len(places)):
            for y in range(x + 1, len(places)):
                (fa, ia), (fb, ib) = sorted((places[x], places[y]))
                if fa == fb and abs(ia - ib) < RUN:
                    continue  # a run overlapping itself (a repeated line), not a copy
                shared[(fa, fb)].update(range(ia, ia + RUN))
    if len(files) < 50:  # a wrong ROOT would find no copy: never a vacuous pass
        sys.exit(f"copies: expected the library's sources under {root}/{{{','.join(DIRS)}}}, found {len(files)} files")
    return {k: (len(v), files[k[0]][min(v)][0]) for k, v in shared.items()}


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else "."
    now = pairs(root)
    if "--list" in sys.argv:
        for (a, b), (n, _) in sorted(now.items(), key=lambda kv: (-kv[1][0], kv[0])):
            print(f"{n} {a} {b}")
        return 0
    listing = os.path.join(os.path.dirname(os.path.abspath(__file__)), "copies.txt")
    listed = read_listing(listing, "LINES FILE_A FILE_B")
    if listed is None:
        return 2
    bad = ratchet(
        now, listed, listing,
        lambda k, n, first: f"{k[0]}:{first}: {n} lines stand again, to the letter, in {k[1]} (expected no copy of "
        f"{RUN} or more lines: make one function serve both; `copies.py . --list` names the pairs)",
        lambda k, n, first, most: f"{k[0]}:{first}: {n} lines stand again in {k[1]}, expected at most its listed {most}",
        lambda k, n: f"{listing}: {k[0]} {k[1]} is listed at {n} lines but shares none now: remove it")
    print(f"copies: {len(now)} pairs of files share runs of {RUN}+ lines, {len(listed)} listed; {bad} findings")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
