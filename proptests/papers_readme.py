#!/usr/bin/env python3
"""README's "The papers in dcad" table from proptests/papers.tsv (issue 46): per section of the papers, how many
statements are covered, one-sided, partial or missing, the library functions that implement them (reference and
fast, by file:symbol as papers.tsv names them) and the tests that hold them.  The sections are the ids' ranges in
../shared/PAPER-ITEMS.md.

Usage: papers_readme.py SOURCE_DIR           prints the Markdown table
       papers_readme.py SOURCE_DIR --check   fails unless README.md holds that table as printed
"""
import collections
import sys


SECTIONS = [(14, "CEF §1–§2"), (21, "CEF §3.1"), (43, "CEF §3.2–§3.4"), (53, "CEF §4"), (63, "CEF §5"), (97, "CEF §6"),
            (110, "CEF §7, Appendix A")]


def section(pid):
    """The paper section of an id of PAPER-ITEMS.md."""
    if pid[0] in "YVN":
        return {"Y": "YM", "V": "V", "N": "found later (CEF (1.6) and others)"}[pid[0]]
    return next(name for last, name in SECTIONS if int(pid) <= last)


def table(source):
    """The Markdown table's lines."""
    out = []
    sections = collections.OrderedDict()
    for line in open(source + "/proptests/papers.tsv", encoding="utf-8").read().split("\n")[1:]:
        if not line:
            continue
        pid, status, ref, fast, tests = line.split("\t")
        s = sections.setdefault(section(pid), {"n": collections.Counter(), "calls": [], "tests": []})
        s["n"][status.split(":")[0]] += 1
        for part in (ref + ", " + fast).split(", "):
            name = part.split(":")[-1].strip()
            if name and name != "-" and name not in s["calls"]:
                s["calls"].append(name)
        for t in tests.split(", "):
            t = t.strip()
            if t and t != "-" and t not in s["tests"]:
                s["tests"].append(t)
    out.append("| section | covered / one-sided / partial / missing | what to call | tests that hold it |")
    out.append("|---|---|---|---|")
    for sec, s in sections.items():
        n = s["n"]
        calls = ", ".join("`%s`" % c for c in s["calls"][:10]) + (" …" if len(s["calls"]) > 10 else "")
        tests = ", ".join(s["tests"][:6]) + (" … (%d in all)" % len(s["tests"]) if len(s["tests"]) > 6 else "")
        out.append("| %s | %d / %d / %d / %d | %s | %s |" % (sec, n["covered"], n["one-sided"], n["partial"],
                                                          n["missing"], calls or "—", tests or "—"))
    return out


def main():
    source = sys.argv[1]
    lines = table(source)
    if "--check" not in sys.argv:
        print("\n".join(lines))
        return 0
    readme = open(source + "/README.md", encoding="utf-8").read()
    if "\n".join(lines) in readme:
        return 0
    print("README.md: expected the papers' table as proptests/papers_readme.py prints it from proptests/papers.tsv, "
          "found another (run: python3 proptests/papers_readme.py . and paste it under \"The papers in dcad\")")
    return 1


if __name__ == "__main__":
    sys.exit(main())
