#!/usr/bin/env python3
"""Size of the code base, for reviews of its structure.

    python3 scripts/code_report.py [--root DIR] [--classes ShellPatch,World,...] [--top 10]

Prints three tables for the product code (every top-level folder with C++ sources, without tests/, build/
and bench/):
  1. lines of .hpp and .cpp per folder;
  2. the longest functions: a definition whose signature starts in column 0 (or column 0 inside a
     namespace, which is how this tree is formatted) counted from that line to the closing brace in
     column 0;
  3. data members and methods per class or struct defined at namespace level in a header (all of them,
     or those named with --classes): a line at the body's indentation that declares something with a
     parameter list is a method, any other declaration a data member (names separated by commas count
     one each); nested types, access labels, using-declarations and static constants are not counted.

It reads the text, not a C++ parse: the counts are for comparing a tree with itself before and after a
change, not a metric to compare with other tools. Standard library only.
"""
import argparse
import os
import re
import sys

SKIP = {"tests", "build", "bench", ".git", ".ci", "docs", "scenes", "examples", "scripts", "cmake"}


def product_files(root):
    for top in sorted(os.listdir(root)):
        path = os.path.join(root, top)
        if top in SKIP or top.startswith(".") or not os.path.isdir(path):
            continue
        for dirpath, _, names in os.walk(path):
            for n in sorted(names):
                if n.endswith((".cpp", ".hpp")):
                    yield top, os.path.join(dirpath, n)


def lines_per_folder(files):
    counts = {}
    for top, path in files:
        with open(path, encoding="utf-8", errors="replace") as f:
            n = sum(1 for _ in f)
        hpp, cpp = counts.get(top, (0, 0))
        counts[top] = (hpp + n, cpp) if path.endswith(".hpp") else (hpp, cpp + n)
    return counts


SIGNATURE = re.compile(r"^[A-Za-z_][\w:<>,*&\s~]*\b([\w:~]+)\s*\(")


def functions(path):
    """(name, first line, length) of the column-0 definitions in a file."""
    with open(path, encoding="utf-8", errors="replace") as f:
        text = f.read().split("\n")
    out = []
    i = 0
    while i < len(text):
        line = text[i]
        m = SIGNATURE.match(line)
        if m and not line.startswith(("namespace", "struct", "class", "enum", "using", "typedef", "#", "template <class")):
            # the body opens on this line or a following signature line, and closes with "}" in column 0
            j = i
            while j < len(text) and "{" not in text[j] and not text[j].rstrip().endswith(";"):
                j += 1
            if j < len(text) and "{" in text[j] and not text[j].rstrip().endswith("};"):
                k = j
                while k < len(text) and not (text[k].startswith("}") and not text[k].startswith("}  // namespace")):
                    k += 1
                if k < len(text) and k > j:
                    out.append((m.group(1), i + 1, k - i + 1))
                    i = k + 1
                    continue
        i += 1
    return out


CLASS = re.compile(r"^(?:class|struct)\s+(\w+)(?:\s+final)?\s*(?::[^{]*)?\{\s*$")


def class_shapes(path, wanted):
    with open(path, encoding="utf-8", errors="replace") as f:
        text = f.read().split("\n")
    shapes = []
    i = 0
    while i < len(text):
        m = CLASS.match(text[i])
        if not m or (wanted and m.group(1) not in wanted):
            i += 1
            continue
        name, members, methods = m.group(1), 0, 0
        i += 1
        statement = ""
        depth = 0
        while i < len(text) and not text[i].startswith("};"):
            line = text[i].split("//")[0]
            i += 1
            stripped = line.strip()
            if depth == 0 and not statement:
                if (not stripped or re.match(r"^(public|private|protected):", stripped) or
                        stripped.startswith(("using ", "friend ", "static constexpr", "static_assert", "enum ",
                                             "template"))):
                    continue
                if re.match(r"^(struct|class|union)\b", stripped):
                    depth_start = line.count("{") - line.count("}")
                    if depth_start > 0 or not stripped.endswith(";"):
                        depth = max(depth_start, 0)
                        if depth == 0:
                            depth = -1  # brace on a later line
                    continue
            if depth != 0:
                if depth == -1:
                    depth = 0
                depth += line.count("{") - line.count("}")
                if depth <= 0 and "};" in line:
                    depth = 0
                continue
            statement += " " + stripped
            opened = statement.count("{") - statement.count("}")
            if opened > 0:
                continue  # an inline body continues
            if not (statement.rstrip().endswith(";") or statement.rstrip().endswith("}")):
                continue
            decl = statement.strip()
            statement = ""
            head = decl.split("=")[0]
            if "(" in head.split("{")[0]:
                methods += 1
            else:
                names = re.sub(r"<[^<>]*>", "", decl.split("{")[0].rstrip(";"))
                names = re.sub(r"=[^,;]*", "", names)  # initialisers may hold commas
                members += names.count(",") + 1
        shapes.append((name, members, methods, path))
        i += 1
    return shapes


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--root", default=os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    ap.add_argument("--classes", default="", help="comma-separated class names (default: all)")
    ap.add_argument("--top", type=int, default=10)
    args = ap.parse_args()
    files = list(product_files(args.root))
    if not files:
        print("code_report: no C++ sources under %s" % args.root, file=sys.stderr)
        return 1

    print("## Lines per folder\n")
    print("| folder | .hpp | .cpp | total |\n|---|---|---|---|")
    total = [0, 0]
    for top, (h, c) in sorted(lines_per_folder(files).items()):
        print("| %s | %d | %d | %d |" % (top, h, c, h + c))
        total[0] += h
        total[1] += c
    print("| **all** | %d | %d | %d |\n" % (total[0], total[1], sum(total)))

    print("## The %d longest functions\n" % args.top)
    print("| lines | function | file:line |\n|---|---|---|")
    funcs = []
    for _, path in files:
        funcs += [(n, os.path.relpath(path, args.root), line, length) for n, line, length in functions(path)]
    funcs.sort(key=lambda f: (-f[3], f[1], f[2]))
    for name, path, line, length in funcs[:args.top]:
        print("| %d | `%s` | %s:%d |" % (length, name, path, line))
    print("\n%d functions, %d over 80 lines\n" % (len(funcs), sum(1 for f in funcs if f[3] > 80)))

    wanted = set(c for c in args.classes.split(",") if c)
    print("## Members and methods per class\n")
    print("| class | data members | methods | header |\n|---|---|---|---|")
    shapes = []
    for _, path in files:
        if path.endswith(".hpp"):
            shapes += class_shapes(path, wanted)
    shapes.sort(key=lambda s: (-(s[1] + s[2]), s[0]))
    for name, members, methods, path in shapes if wanted else shapes[:args.top]:
        print("| %s | %d | %d | %s |" % (name, members, methods, os.path.relpath(path, args.root)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
