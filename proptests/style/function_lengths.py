#!/usr/bin/env python3
"""The function-length ratchet (issue 47): no function in the library (reference/, fast/, cli/) is longer than
LIMIT lines, save those listed in long_functions.txt at no more than their listed length; an entry whose
function has shrunk to LIMIT or below (or is gone) must leave the list, so the list only shrinks.

Lengths are counted on the clang-formatted source (.clang-format, 120 columns) from the first line of the
signature to the closing brace.  Comments and literals are blanked before braces are matched.

Usage: function_lengths.py ROOT [--list]   (--list prints today's long functions in the list's format)
"""
import os
import re
import sys

LIMIT = 80
DIRS = ("reference", "fast", "cli")
SCOPES = re.compile(r"\b(namespace|class|struct|union|enum)\b")
CONTROL = re.compile(r"^\s*(if|for|while|switch|catch|else|do|try)\b")


def blank(text, literals=True):
    """The text with comments, string and character literals (`literals`) replaced by spaces (newlines kept)."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif text.startswith('R"', i) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            m = re.match(r'R"([^(\s]*)\(', text[i:])
            end = text.find(")" + m.group(1) + '"', i) if m else -1
            j = n if end < 0 else end + len(m.group(1)) + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]) if literals else text[i:j])
            i = j
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            if c == "'" and i > 0 and text[i - 1].isalnum():  # a digit separator (1'000)
                out.append(c)
                i += 1
                continue
            out.append(" " * (min(j + 1, n) - i) if literals else text[i:min(j + 1, n)])
            i = j + 1
        else:
            out.append(c)
            i += 1
    return "".join(out)


def functions(path):
    """(name, first line, length) of every function body at namespace or class scope."""
    text = blank(open(path, encoding="utf-8").read())
    stack, found = [], []  # stack: (kind, start line, name)
    head_start = 0  # where the current declaration's text starts
    line = 1
    for i, c in enumerate(text):
        if c == "\n":
            line += 1
        if c in ";{}":
            if c == "{":
                head = text[head_start:i]
                outer = all(k == "scope" for k, _, _ in stack)
                if SCOPES.search(head) and "(" not in head.split("{")[0].split("=")[0]:
                    kind = "scope"
                elif outer and ")" in head and not head.rstrip().endswith("=") and not CONTROL.match(head):
                    kind = "function"
                else:
                    kind = "other"
                stripped = head.lstrip()
                first = line - head[len(head) - len(stripped):].count("\n") if stripped else line
                first = line - stripped.count("\n") if stripped else line
                name = ""
                if kind == "function":
                    sig = " ".join(stripped.split())
                    sig = re.sub(r"^template\s*<.*?>\s*", "", sig)
                    m = re.search(r"([~\w:]+(?:operator\S*)?)\s*\(", sig)
                    name = m.group(1) if m else sig[:40]
                stack.append((kind, first, name))
            elif c == "}" and stack:
                kind, first, name = stack.pop()
                if kind == "function":
                    found.append((name, first, line - first + 1))
            head_start = i + 1
    return found


def scan(root):
    out = {}
    for d in DIRS:
        for dp, _, fns in os.walk(os.path.join(root, d)):
            for f in sorted(fns):
                if not f.endswith((".cpp", ".hpp")):
                    continue
                p = os.path.join(dp, f)
                rel = os.path.relpath(p, root)
                for name, first, n in functions(p):
                    if n > LIMIT:
                        key = (rel, name)
                        out[key] = max(out.get(key, (0, 0)), (n, first))
    return out


def read_listing(listing, form):
    """{(A, B): N} from the listing's lines `N A B` (text after # is a comment); None after printing a bad line."""
    listed = {}
    for k, raw in enumerate(open(listing, encoding="utf-8"), 1):
        raw = raw.split("#")[0].strip()
        if not raw:
            continue
        parts = raw.split()
        if len(parts) != 3 or not parts[0].isdigit():
            print(f"{listing}:{k}: expected '{form}', found '{raw}'")
            return None
        listed[(parts[1], parts[2])] = int(parts[0])
    return listed


def ratchet(now, listed, listing, unlisted, over, gone):
    """The ratchet's findings, printed: a key of `now` ({(A, B): (N, line)}) not listed (unlisted(key, N, line)) or
    above its listed N (over(key, N, line, listed N)), and a listed key gone (gone(key, listed N)) or below its
    listed N (then the list must be lowered).  Returns how many."""
    bad = 0
    for key, (n, first) in sorted(now.items()):
        if key not in listed:
            print(unlisted(key, n, first))
            bad += 1
        elif n > listed[key]:
            print(over(key, n, first, listed[key]))
            bad += 1
    for key, n in sorted(listed.items()):
        if key not in now:
            print(gone(key, n))
            bad += 1
        elif now[key][0] < n:
            print(f"{listing}: {key[0]} {key[1]} is listed at {n} but is now {now[key][0]}: lower it")
            bad += 1
    return bad


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else "."
    long_now = scan(root)
    if "--list" in sys.argv:
        for (rel, name), (n, _) in sorted(long_now.items(), key=lambda kv: (-kv[1][0], kv[0])):
            print(f"{n} {rel} {name}")
        return 0
    listing = os.path.join(os.path.dirname(os.path.abspath(__file__)), "long_functions.txt")
    listed = read_listing(listing, "LENGTH FILE FUNCTION")
    if listed is None:
        return 2
    bad = ratchet(
        long_now, listed, listing,
        lambda k, n, first: f"{k[0]}:{first}: {k[1]} is {n} lines, expected at most {LIMIT} (split it; the list of "
        "exceptions only shrinks)",
        lambda k, n, first, most: f"{k[0]}:{first}: {k[1]} is {n} lines, expected at most its listed {most}",
        lambda k, n: f"{listing}: {k[0]} {k[1]} is listed at {n} lines but is now at most {LIMIT} (or gone): remove it")
    print(f"function lengths: {len(long_now)} functions over {LIMIT} lines, {len(listed)} listed; {bad} findings")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
