#!/usr/bin/env python3
"""Mutation testing (issue 15): do the tests fail when the code is wrong?

    python3 proptests/mutate.py [--count N] [--seed S] [--dirs reference,fast,cli] [--keep] [--start K]

Picks N single-token mutants at random (seeded) in the C++ sources of the given directories — an
arithmetic, comparison or logical operator swapped (+ -, < <=, > >=, == !=, && ||), a numeric
literal changed (0 ↔ 1, k → k + 1, sign flipped), true ↔ false — and for each one, in a git
worktree of HEAD under build-mutate/ (your checkout is never touched): applies it, rebuilds and
runs the tests (ctest's own test list, every test but the `install` label).  A mutant is
  killed     when a test fails (or times out),
  survived   when every test passes — a test is missing or the change is equivalent,
  stillborn  when it does not compile (not counted in the score).
Prints one line per mutant (with the test executable and the tests that killed it) and the score
killed / (killed + survived); writes every line to build-mutate/mutants.txt.

The verdict is that of a full rebuild and a full ctest run, reached sooner:
  * test executables are built and run one at a time, the one that killed most mutants of the same
    file (then directory) so far first, and the first failure ends the mutant (killed);
  * an executable the rebuild did not relink (and, for the CLI tests, whose `dcad` binary did not
    change either) cannot see the mutant: its tests are the unmutated run's, which passed;
  * ccache (`bash .ci/setup --mutate` installs it) turns the rebuild after each revert into cache hits.
  * a test that runs 5x as long as the slowest test of the unmutated run (at least 60 s) kills the
    mutant: a moved loop bound that hangs costs a minute, not ctest's 10.
A survivor therefore cost a full rebuild and every test; a killed mutant usually one executable.
Ctrl-C (or kill) reverts the mutant under test, prints the score so far and the --start that resumes the sample.
Standard library only.
"""
import argparse
import json
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import time

SWAPS = [(" + ", " - "), (" - ", " + "), (" < ", " <= "), (" <= ", " < "), (" > ", " >= "), (" >= ", " > "),
         (" == ", " != "), (" != ", " == "), (" && ", " || "), (" || ", " && "), ("true", "false"), ("false", "true")]
NUMBER = re.compile(r"(?<![\w.])(\d+(?:\.\d+)?(?:e[+-]?\d+)?)(?![\w.])")


def in_string_or_comment(line, pos):
    code = line.split("//", 1)[0]
    if pos >= len(code):
        return True
    return code[:pos].count('"') % 2 == 1


def inside_literal(line, pos):
    """Whether `pos` is inside a string or character literal or a // comment, reading escapes (\\")
    and digit separators (200'000).  The sampler's in_string_or_comment counts quotes only, and is kept
    so that a seed picks the same mutants as before; a pick that this exact test puts in a literal is
    skipped (a changed message, and a rebuild of everything that includes it, for nothing)."""
    quote, i = None, 0
    while i < pos:
        c = line[i]
        if quote:
            if c == "\\":
                i += 2
                continue
            if c == quote:
                quote = None
        elif line.startswith("//", i):
            return True
        elif c == '"' or (c == "'" and not (line[i - 1:i].isalnum() and line[i + 1:i + 2].isalnum())):
            quote = c
        i += 1
    return quote is not None


def candidates(root, dirs):
    out = []
    for d in dirs:
        for base, _, files in os.walk(os.path.join(root, d)):
            for f in sorted(files):
                if not f.endswith((".cpp", ".hpp")):
                    continue
                path = os.path.relpath(os.path.join(base, f), root)
                with open(os.path.join(root, path), encoding="utf-8") as fh:
                    lines = fh.read().split("\n")
                for i, line in enumerate(lines):
                    s = line.strip()
                    if not s or s.startswith(("//", "#", "*", "/*")) or "static_assert" in s:
                        continue
                    for a, b in SWAPS:
                        start = 0
                        while (k := line.find(a, start)) >= 0:
                            if a in ("true", "false") and (line[k - 1:k].isalnum() or line[k + len(a):k + len(a) + 1].isalnum()):
                                start = k + 1
                                continue
                            if not in_string_or_comment(line, k):
                                out.append((path, i, k, a, b))
                            start = k + 1
                    for m in NUMBER.finditer(line):
                        if in_string_or_comment(line, m.start()):
                            continue
                        v = m.group(1)
                        new = "1" if v == "0" else "0" if v == "1" else ("-" + v if "." in v or "e" in v else str(int(v) + 1))
                        out.append((path, i, m.start(), v, new))
    return out


def run(cmd, cwd, timeout, env=None):
    return run_output(cmd, cwd, timeout, env)[0]


def run_output(cmd, cwd, timeout, env=None):
    """(return code or "timeout", standard output)."""
    try:
        done = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=timeout, env=env)
        return done.returncode, done.stdout
    except subprocess.TimeoutExpired as e:
        out = e.stdout.decode(errors="replace") if isinstance(e.stdout, bytes) else (e.stdout or "")
        return "timeout", out


def failed_tests(ctest_output):
    """The names under ctest's "The following tests FAILED:" ("  12 - Suite.Name (Failed)"), so that a kill
    names its test, not only its executable: a kill by a test that cannot see the mutant is a flaky test."""
    names, listing = [], False
    for row in ctest_output.splitlines():
        if "The following tests FAILED" in row:
            listing = True
        elif listing and (m := re.match(r"\s*\d+ - (\S+)", row)):
            names.append(m.group(1))
    return names


def test_executables(build, tree):
    """{executable path: [ctest test numbers]} from ctest's own list (every test but label `install`)."""
    out = subprocess.run(["ctest", "--test-dir", build, "--show-only=json-v1"], cwd=tree, capture_output=True,
                         text=True, check=True).stdout
    groups = {}
    for number, t in enumerate(json.loads(out)["tests"], 1):
        labels = [p["value"] for p in t.get("properties", []) if p["name"] == "LABELS"]
        if any("install" in (l if isinstance(l, list) else [l]) for l in labels):
            continue
        groups.setdefault(t["command"][0], []).append(number)
    return groups


def test_timeout(build):
    """5x the slowest test of the unmutated run (ctest's CTestCostData: name, runs, mean seconds), at least
    60 s: a mutant that hangs (a loop bound moved) is killed in about a minute, not ctest's 10."""
    slowest = 0.0
    try:
        with open(os.path.join(build, "Testing", "Temporary", "CTestCostData.txt")) as f:
            for row in f:
                parts = row.split()
                if len(parts) == 3:
                    slowest = max(slowest, float(parts[2]))
    except (OSError, ValueError):
        return 300
    return max(60, int(5 * slowest + 1))


def binary_users(groups, build, binary):
    """The test executables that run the dcad binary (compiled with -DDCAD_BINARY=…): they see a mutant
    through it too.  Read from CMake's flags.make of each target; searching the executable for the path
    missed cli_check, where GCC stores the literal in pieces (its 7 tests never saw a mutant of cli/)."""
    flags = {}  # target name -> its flags.make files (one walk of the build tree)
    for root, _, files in os.walk(build):
        if root.endswith(".dir") and "flags.make" in files:
            flags.setdefault(os.path.basename(root)[:-4], []).append(os.path.join(root, "flags.make"))
    users = set()
    for exe in groups:
        found = flags.get(os.path.basename(exe))
        if found:
            if any("DCAD_BINARY" in open(f, encoding="utf-8", errors="replace").read() for f in found):
                users.add(exe)
        elif binary.encode() in open(exe, "rb").read():  # not a Makefile build: the path, where it is whole
            users.add(exe)
    return users


def mtime(path):
    try:
        return os.stat(path).st_mtime_ns
    except FileNotFoundError:
        return None


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--count", type=int, default=20)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--dirs", default="reference,fast,cli")
    ap.add_argument("--keep", action="store_true", help="keep the worktree's build for the next run")
    ap.add_argument("--start", type=int, default=1,
                    help="begin at mutant START of the seeded sample (continue an interrupted run: same --count, "
                         "--seed and commit; mutants.txt is appended to)")
    args = ap.parse_args()
    # Ctrl-C, and kill (SIGTERM), end the run cleanly — also when started in the background, where a shell
    # leaves SIGINT ignored
    signal.signal(signal.SIGINT, signal.default_int_handler)
    signal.signal(signal.SIGTERM, signal.default_int_handler)
    root = subprocess.run(["git", "rev-parse", "--show-toplevel"], capture_output=True, text=True, check=True).stdout.strip()
    work = os.path.join(root, "build-mutate")
    tree, build = os.path.join(work, "tree"), os.path.join(work, "build")
    os.makedirs(work, exist_ok=True)
    if not os.path.isdir(tree):
        subprocess.run(["git", "worktree", "add", "--detach", tree, "HEAD"], cwd=root, check=True, capture_output=True)
    else:
        subprocess.run(["git", "checkout", "--detach", "--force", subprocess.run(["git", "rev-parse", "HEAD"], cwd=root,
                        capture_output=True, text=True).stdout.strip()], cwd=tree, check=True, capture_output=True)
    env = dict(os.environ, CCACHE_DIR=os.path.join(work, "ccache"))
    launcher = ["-DCMAKE_CXX_COMPILER_LAUNCHER=ccache"] if shutil.which("ccache") else []
    if not launcher:
        print("[mutate] no ccache (bash .ci/setup --mutate): every revert rebuilds for real", flush=True)
    print(f"[mutate] building the unmutated tree in {build} (once)", flush=True)
    if run(["cmake", "-S", tree, "-B", build, "-DCMAKE_BUILD_TYPE=Release"] + launcher, tree, 600, env) != 0 or \
            run(["cmake", "--build", build, "-j2"], tree, 7200, env) != 0:
        sys.exit("mutate: the unmutated tree does not build")
    if run(["ctest", "--test-dir", build, "-j2", "-LE", "install"], tree, 1800, env) != 0:
        sys.exit("mutate: the unmutated tree fails its tests: fix that first")
    groups = test_executables(build, tree)
    timeout = test_timeout(build)
    print(f"[mutate] a test running longer than {timeout} s kills the mutant (5x the slowest unmutated test, at least 60 s)",
          flush=True)
    binary = os.path.join(build, "dcad")
    uses_binary = binary_users(groups, build, binary)
    kills = {}  # (scope, executable) -> mutants it killed, scope = file or directory
    pool = candidates(tree, args.dirs.split(","))
    rng = random.Random(args.seed)
    picks = rng.sample(pool, min(args.count, len(pool)))
    log = open(os.path.join(work, "mutants.txt"), "a" if args.start > 1 else "w")
    tally = {"killed": 0, "survived": 0, "stillborn": 0}
    n = args.start
    try:
        for n, pick in enumerate(picks, 1):
            if n >= args.start:
                one_mutant(n, len(picks), pick, tree, build, env, groups, uses_binary, binary, kills, tally, log, timeout)
    except KeyboardInterrupt:  # Ctrl-C: the mutant was reverted (one_mutant's finally); say where to resume
        print(f"[mutate] interrupted: resume with --start {n} (same --count, --seed, commit)", flush=True)
    run(["cmake", "--build", build, "-j2"], tree, 7200, env)  # back to the unmutated build
    scored = tally["killed"] + tally["survived"]
    summary = (f"mutation score {tally['killed']}/{scored} = {100.0 * tally['killed'] / max(scored, 1):.0f} % "
               f"({tally['stillborn']} stillborn, {tally.get('in a literal', 0)} skipped inside literals; seed {args.seed}; mutants {args.start}..{args.start + sum(tally.values()) - 1} of {len(picks)}; "
               f"{len(pool)} candidate mutants in {args.dirs})")
    print(summary)
    log.write(summary + "\n")
    if not args.keep:
        subprocess.run(["git", "worktree", "remove", "--force", tree], cwd=root, capture_output=True)


def one_mutant(n, total, pick, tree, build, env, groups, uses_binary, binary, kills, tally, log, timeout):
    """Apply one mutant, reach its verdict, revert it (also when interrupted)."""
    path, i, k, a, b = pick
    full = os.path.join(tree, path)
    with open(full, encoding="utf-8") as fh:
        original = fh.read()
    lines = original.split("\n")
    if inside_literal(lines[i], k):
        tally["in a literal"] = tally.get("in a literal", 0) + 1
        print(f"[{n}/{total}] SKIPPED   {path}:{i + 1}: '{a.strip()}' -> '{b.strip()}' inside a literal", flush=True)
        return
    lines[i] = lines[i][:k] + b + lines[i][k + len(a):]
    with open(full, "w", encoding="utf-8") as fh:
        fh.write("\n".join(lines))
    try:
        t0 = time.time()
        scopes = (path, os.path.dirname(path))
        order = sorted(groups, key=lambda e: (-kills.get((scopes[0], e), 0), -kills.get((scopes[1], e), 0), e))
        verdict, killer = "survived", ""
        binary_before = mtime(binary)
        for exe in order:
            before = mtime(exe)
            target = os.path.basename(exe)
            if run(["cmake", "--build", build, "-j2", "--target", target], tree, 3600, env) != 0:
                verdict, killer = "stillborn", target
                break
            if mtime(exe) == before and not (exe in uses_binary and mtime(binary) != binary_before):
                continue  # not relinked: it runs the unmutated code, whose tests passed
            numbers = ",".join(str(t) for t in groups[exe])
            tested, output = run_output(["ctest", "--test-dir", build, "-j2", "--timeout", str(timeout), "-I", f"0,0,0,{numbers}"],
                                        tree, 3600, env)
            if tested != 0:
                names = failed_tests(output)
                verdict, killer = "killed", target + (f" ({', '.join(names[:3])}{', …' if len(names) > 3 else ''})" if names else
                                                       " (ctest timed out)" if tested == "timeout" else "")
                for s in scopes:
                    kills[(s, exe)] = kills.get((s, exe), 0) + 1
                break
        if verdict == "survived" and run(["cmake", "--build", build, "-j2"], tree, 3600, env) != 0:
            verdict = "stillborn"  # a target that no test uses does not compile
    finally:
        with open(full, "w", encoding="utf-8") as fh:
            fh.write(original)
    tally[verdict] += 1
    by = f" by {killer}" if verdict == "killed" else ""
    line = f"{verdict.upper():9} {path}:{i + 1}: '{a.strip()}' -> '{b.strip()}'{by}   ({time.time() - t0:.0f} s)   {lines[i].strip()[:100]}"
    print(f"[{n}/{total}] {line}", flush=True)
    log.write(line + "\n")
    log.flush()


if __name__ == "__main__":
    main()
