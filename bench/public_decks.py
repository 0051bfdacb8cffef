#!/usr/bin/env python3
"""Issue 45's acceptance corpus: public linear SPICE decks nobody here wrote, run through `dcad solve`.

The decks themselves are not in this repository (their licences and the rule that fetched code stays
out of commits); bench/public_decks.tsv lists each one's origin (source, repository, commit, path,
licence).  Put a copy of those repositories' files under CORPUS/<source>/<path> (for instance from
`git --git-dir=… show COMMIT:PATH`), then:

    /usr/bin/python3 bench/public_decks.py build/dcad CORPUS [--out bench/results/public_decks.md]

Each deck runs once, `dcad solve --json --with none --dialect D DECK` in the deck's own directory (its
.include files beside it), 60 s at most.  D is the deck's simulator (`dialect`): ngspice's decks are ngspice's,
gnucap's gnucap's, Xyce's Xyce's — or hspice where Xyce's own test script runs the deck with -hspice-ext.  The table counts accepted decks (exit 0) per source and groups the
refusals by their message (file names and numbers folded), so a refusal that is not true shows.
"""
import collections
import csv
import glob
import os
import re
import subprocess
import sys
import time


def fold(message):
    """A refusal's message with what varies between decks folded: file:line, quoted text, numbers."""
    m = re.sub(r"^\S+?:\d+: ", "", message)
    m = re.sub(r"\"[^\"]*\"", '"…"', m)
    m = re.sub(r"\b[\w.+-]*\d[\w.+-]*\b", "#", m)
    return m[:160]


# Decks their origin wrote to be refused: Xyce's tests of its error messages (Netlists/Message/, except the
# ones named for a warning, which Xyce runs) and decks whose name says they fail (Xyce's INVALID_CHARS/*_fails,
# gnucap's *.error*, Xyce's bad_*, *_missing, dup-*, busted).  They are counted apart: for them a true refusal is
# the right answer, and the table shows how many of them dcad refuses.
# Not `_dup.`: Certification_Tests/BUG_1686/bug_1686_dup.cir is meant to run (bug_1686.cir.sh diffs its output
# against bug_1686a.cir's); BUG_701's dup-*.cir are the duplicate-name errors.
MEANT_TO_FAIL = re.compile(r"(^Netlists/Message/(?!.*[Ww]arning))|_fails?[._]|\.error\d|/bad_|/Bad_|_is_missing|missing_ends|/dup-|bogo", re.I)


# Xyce_Regression's harness says it too: a test script DECK.sh that runs its own deck ($CIRFILE, the argument the
# harness passes) with runAndCheckError or runAndCheckGroupedError expects Xyce to exit with an error
# (TestScripts/XyceRegression/Tools.pm: "Xyce should EXIT WITH ERROR, and not doing so is a failure").
EXPECTS_ERROR = re.compile(r"runAndCheck(?:Grouped)?Error\(\s*\$CIRFILE\s*,")
CORPUS = None  # set by main(): where the decks' test scripts are

# Refusals of decks that are not one fixed linear R/L/C/K/V/I circuit with deterministic sources: reported as a
# second figure beside the first (issue 45 asks for >= 97 % of "the public linear decks"; which decks count as
# linear is the reader's call, so both figures are printed and the first stays the headline).  Matched on dcad's
# own refusal message.
OUTSIDE = [
    ("a random source or value (rand, trnoise)", re.compile(r"random", re.I)),
    ("a script or card that changes the circuit (.alter, .delete, .fault, mc_source, .preprocess)",
     re.compile(r"a command that changes the circuit|which changes it before|found \.preprocess", re.I)),
    ("a behavioural source in the time (a `time` expression)", re.compile(r'unknown parameter "time"', re.I)),
    ("an AC-only quantity (freq, hertz, complex values)", re.compile(r'unknown parameter "(freq|hertz)"|"complex', re.I)),
    ("a conditional netlist (.if)", re.compile(r"found \.if\b", re.I)),
    ("a nonlinear element (gnucap .vccap; a PWL, FIT or TABLE resistance)", re.compile(r"\.vccap|a nonlinear element", re.I)),
]
# Values the deck leaves to a file its test script names on Xyce's command line (-prf, Dakota's parameter files):
# a refusal that says a name is undefined, of a deck whose DECK.sh passes -prf or runs Dakota.
FROM_OUTSIDE = "values set from outside the deck (Xyce's -prf parameter file, Dakota)"



def outside_linear(first, path=None):
    label = next((label for label, pattern in OUTSIDE if pattern.search(first)), None)
    script = os.path.join(CORPUS, "xyce", path + ".sh") if CORPUS and path else ""
    if not label and "a name no .param defines" in first and os.path.isfile(script):
        if re.search(r"-prf|dakota", open(script, errors="replace").read(), re.I):
            return FROM_OUTSIDE
    return label


# ... or a deck whose name the script makes from its own (BUG_630_SON/vpwl.cir.sh: `$CIRFILE1 =~
# s/.cir/RepeatFail.cir/` then runAndCheckError($CIRFILE1, …) expects vpwlRepeatFail.cir to fail).
DERIVED = re.compile(r"\$(\w+)\s*=~\s*s/\.?cir/(\w+)\.cir/")


def meant_to_fail(path):
    if MEANT_TO_FAIL.search(path):
        return True
    if not CORPUS:
        return False
    script = os.path.join(CORPUS, "xyce", path + ".sh")
    if os.path.isfile(script) and EXPECTS_ERROR.search(open(script, errors="replace").read()):
        return True
    folder = os.path.dirname(os.path.join(CORPUS, "xyce", path))
    for sh in glob.glob(os.path.join(folder, "*.cir.sh")):
        text = open(sh, errors="replace").read()
        for var, suffix in DERIVED.findall(text):
            derived = os.path.basename(sh)[:-len(".cir.sh")] + suffix + ".cir"
            if derived == os.path.basename(path) and re.search(r"runAndCheck(?:Grouped)?Error\(\s*\$" + var + r"\s*,", text):
                return True
    return False


def dialect(source, deck):
    """The simulator a deck was written for, as `dcad --dialect` names it: its source's, except a Xyce deck
    whose test script (DECK.sh beside it, as Xyce_Regression runs it) passes -hspice-ext, or an HSPICE deck
    of Xyce's XDM tests (*.hspice)."""
    script = deck + ".sh"
    if source == "xyce" and os.path.isfile(script) and "hspice-ext" in open(script, errors="replace").read():
        return "hspice"
    if deck.endswith(".hspice"):  # Xyce's XDM tests: HSPICE decks for its translator
        return "hspice"
    return source


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    global CORPUS
    dcad, corpus = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    CORPUS = corpus
    out = sys.argv[sys.argv.index("--out") + 1] if "--out" in sys.argv else os.path.join(os.path.dirname(__file__), "results", "public_decks.md")
    listing = os.path.join(os.path.dirname(os.path.abspath(__file__)), "public_decks.tsv")
    rows = list(csv.DictReader(open(listing), delimiter="\t"))
    per_source = collections.defaultdict(lambda: [0, 0, 0, 0])  # present, accepted, refused, other
    causes = collections.defaultdict(list)
    others = []
    accepted_failing, refused_failing = [], []  # decks meant to fail: accepted (to look at), refused (with the reason)
    t_all = time.monotonic()
    for r in rows:
        deck = os.path.join(corpus, r["source"], r["path"])
        if not os.path.isfile(deck):
            continue
        if meant_to_fail(r["path"]):
            counts = per_source[r["source"] + " (meant to fail)"]
        else:
            counts = per_source[r["source"]]
        counts[0] += 1
        try:
            p = subprocess.run([dcad, "solve", "--json", "--with", "none", "--dialect", dialect(r["source"], deck), os.path.basename(deck)], cwd=os.path.dirname(deck),
                               capture_output=True, timeout=60)
            code, err = p.returncode, p.stderr.decode("utf-8", "replace")
        except subprocess.TimeoutExpired:
            code, err = "timeout", ""
        first = next((l for l in err.splitlines() if l.strip() and not l.startswith(("warning:", "note:"))), "")
        if code == 0:
            counts[1] += 1
            if meant_to_fail(r["path"]):
                accepted_failing.append((r["source"], r["path"]))
        elif code == 1:
            counts[2] += 1
            (refused_failing if meant_to_fail(r["path"]) else causes[fold(first)]).append((r["source"], r["path"], first))
        else:
            counts[3] += 1
            others.append((r["source"], r["path"], code, first))
    seconds = time.monotonic() - t_all
    valid = {s: c for s, c in per_source.items() if not s.endswith("(meant to fail)")}
    present = sum(c[0] for c in valid.values())
    accepted = sum(c[1] for c in valid.values())
    failing = [c for s, c in per_source.items() if s.endswith("(meant to fail)")]
    outside = collections.Counter(outside_linear(first, path) for decks in causes.values() for _, path, first in decks)
    outside.pop(None, None)
    n_out = sum(outside.values())
    with open(out, "w") as f:
        f.write("# Public linear decks through `dcad solve` (issue 45)\n\n")
        f.write("`/usr/bin/python3 bench/public_decks.py build/dcad CORPUS` — %d decks present of %d listed, %.0f s.\n\n" % (present + sum(c[0] for c in failing), len(rows), seconds))
        f.write("| source | decks | accepted | refused (exit 1) | other exit |\n|---|---|---|---|---|\n")
        for s, c in sorted(per_source.items()):
            f.write("| %s | %d | %d (%.1f %%) | %d | %d |\n" % (s, c[0], c[1], 100.0 * c[1] / max(c[0], 1), c[2], c[3]))
        f.write("| all meant to run | %d | %d (%.1f %%) | %d | %d |\n" % (present, accepted, 100.0 * accepted / max(present, 1),
                                                                     sum(c[2] for c in valid.values()), sum(c[3] for c in valid.values())))
        f.write("| all meant to fail | %d | %d | %d | %d |\n\n" % tuple(sum(c[k] for c in failing) for k in range(4)))
        f.write("\nOf the %d decks meant to run, %d are refused for a feature outside one fixed linear R/L/C/K/V/I circuit "
                "with deterministic sources (`OUTSIDE` in this script, matched on dcad's message): %s.  Without them: "
                "%d of %d accepted (%.1f %%).  The headline stays the figure over all of them.\n\n" % (
                    present, n_out, "; ".join("%d %s" % (n, label) for label, n in outside.most_common()),
                    accepted, present - n_out, 100.0 * accepted / max(present - n_out, 1)))
        f.write("A deck is *meant to fail* when its origin wrote it to be refused (`MEANT_TO_FAIL` in this script: Xyce's\n"
                "Netlists/Message/ tests of error messages, names with _fails, .error, bad_, _is_missing, missing_ends, /dup-,\n"
                "bogo; and Xyce decks whose test script runs them with runAndCheckError, expecting Xyce to exit with an\n"
                "error); for those a true refusal is the right answer.  The percentage is over the decks meant to run.\n\n")
        f.write("## Refusals by cause\n\n")
        for cause, decks in sorted(causes.items(), key=lambda kv: -len(kv[1])):
            f.write("- **%d** — `%s`\n" % (len(decks), cause.replace("`", "'")))
            for s, path, first in decks[:3]:
                f.write("  - %s `%s`: %s\n" % (s, path, first.replace("`", "'")[:300]))
        f.write("\n## Decks meant to fail\n\nRefused (%d), each with dcad's reason:\n\n" % len(refused_failing))
        for src, path, first in refused_failing:
            f.write("- %s `%s`: %s\n" % (src, path, first.replace("`", "'")[:200]))
        f.write("\nAccepted (%d) — the deck's fault is one dcad does not see in a transient, or one it reads otherwise:\n\n" % len(accepted_failing))
        for src, path in accepted_failing:
            f.write("- %s `%s`\n" % (src, path))
        if others:
            f.write("\n## Other exits (crashes, internal errors, timeouts)\n\n")
            for s, path, code, first in others:
                f.write("- %s `%s`: exit %s, %s\n" % (s, path, code, first[:300]))
    print("%d of %d decks meant to run accepted (%.1f %%; %.1f %% of the %d within one fixed linear circuit); "
          "%d of %d meant to fail refused; table in %s" % (
              accepted, present, 100.0 * accepted / max(present, 1), 100.0 * accepted / max(present - n_out, 1),
              present - n_out, sum(c[2] for c in failing), sum(c[0] for c in failing), out))


if __name__ == "__main__":
    main()
