#!/usr/bin/env python3
"""The layers point only downwards, and so do the modules inside a layer
(docs/architecture.md).

1. Every `#include "<folder>/<file>.h"` in a library folder must name a
   folder of the same or a lower layer: io < sim < common < estimation <
   discovery < design < tune < report < run < fleet; apps/, python/, bench/,
   fuzz/ and tests/ sit on top and may include any layer. CMake links static
   libraries whatever their includes say, so this is what keeps a cycle
   between layers from coming back. Every folder holding library code must
   be in the list.
2. Inside a layer, a module is a header and its source of the same stem
   (`fit.h`, `fit.cc`; `internal/fitter.h`, `internal/fitter.cc`); module A
   depends on module B when A's header or source includes B's header. No
   cycle of such dependencies (Tarjan's strongly connected components).
3. A layer's `internal/` headers are its own: included by its files and the
   tests only, never by its public headers (which are installed without
   them) nor by another layer.
4. No function of a library folder is longer than MAX_FUNCTION_LINES lines
   from its opening to its closing brace: a long procedure is a class with a
   method per step (docs/architecture.md).

Each check first runs on a made-up case that must fail (so that it can).

    layering_test.py --root SOURCE_DIR
"""
import argparse
import os
import re
import sys

LAYERS = ["io", "sim", "common", "estimation", "discovery", "design", "tune", "report",
          "run", "fleet"]
TOP = ["apps", "python", "bench", "fuzz", "tests"]
INCLUDE = re.compile(r'^\s*#\s*include\s+"([\w.-]+)/[\w./-]+"', re.M)
MODULE_INCLUDE = re.compile(r'^\s*#\s*include\s+"([\w.-]+)/((?:internal/)?[\w.-]+)\.h"', re.M)
INTERNAL_INCLUDE = re.compile(r'^\s*#\s*include\s+"([\w.-]+)/internal/[\w./-]+"', re.M)
MAX_FUNCTION_LINES = 120


def upward_includes(folder, text, known):
    """The (line, included folder) pairs of `text` that point above `folder`."""
    rank = {name: k for k, name in enumerate(LAYERS)}
    out = []
    for m in INCLUDE.finditer(text):
        target = m.group(1)
        if target in rank and rank[target] > rank[folder]:
            line = text.count("\n", 0, m.start()) + 1
            out.append((line, target))
        elif target not in rank and target not in known:
            line = text.count("\n", 0, m.start()) + 1
            out.append((line, target + " (not a layer)"))
    return out


def internal_includes(folder, name, text):
    """The (line, included header) pairs of `text` (file `name` of `folder`,
    e.g. "fit.h" or "internal/fitter.cc") that break the internal rule."""
    out = []
    public_header = name.endswith(".h") and not name.startswith("internal/")
    for m in INTERNAL_INCLUDE.finditer(text):
        if m.group(1) != folder or public_header:
            line = text.count("\n", 0, m.start()) + 1
            out.append((line, m.group(0).split('"')[1]))
    return out


def module_cycles(folder, files):
    """The include cycles between the modules of `folder`, each a sorted list
    of module stems; `files` maps a file name (x.h, x.cc, internal/y.h) to
    its text."""
    edges = {}
    for name, text in files.items():
        stem = name.rsplit(".", 1)[0]
        edges.setdefault(stem, set())
        for m in MODULE_INCLUDE.finditer(text):
            if m.group(1) == folder and m.group(2) != stem:
                edges[stem].add(m.group(2))
    index, low, on_stack, stack, cycles = {}, {}, set(), [], []

    def connect(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(edges.get(v, ())):
            if w not in edges:
                continue
            if w not in index:
                connect(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                cycles.append(sorted(component))

    sys.setrecursionlimit(max(1000, 4 * len(edges)))
    for v in sorted(edges):
        if v not in index:
            connect(v)
    return cycles


def code_only(text):
    """`text` with comments, string and character literals and preprocessor
    lines blanked, its line breaks kept."""
    out, i, n = [], 0, len(text)
    while i < n:
        if text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
            continue
        if text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append("\n" * text.count("\n", i, j))
            i = j
            continue
        raw = re.match(r'R"([^(\s]*)\(', text[i:i + 20]) if text[i] == "R" else None
        if raw and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            end = ")" + raw.group(1) + '"'
            j = text.find(end, i)
            j = n if j < 0 else j + len(end)
            out.append('""' + "\n" * text.count("\n", i, j))
            i = j
            continue
        if text[i] in "\"'":
            quote, j = text[i], i + 1
            while j < n and text[j] != quote:
                j += 2 if text[j] == "\\" else 1
            out.append(quote * 2)
            i = j + 1
            continue
        out.append(text[i])
        i += 1
    lines = "".join(out).split("\n")
    return "\n".join("" if line.lstrip().startswith("#") else line for line in lines)


def long_functions(text, limit):
    """The (first line, lines, name) of each function body in `text` (at
    namespace or class scope) longer than `limit` lines, braces included."""
    code = code_only(text)
    out, stack, head_start = [], [], 0
    for i, c in enumerate(code):
        if c == "{":
            kind, name = "block", ""
            if not stack or stack[-1][0] in ("scope", "class"):
                head = " ".join(code[head_start:i].split())
                if re.match(r"^(template\s*<.*>\s*)?(namespace|extern)\b", head):
                    kind = "scope"
                elif re.match(r"^(template\s*<.*>\s*)?(class|struct|union|enum)\b", head):
                    kind = "class"
                elif "(" in head and not head.endswith("="):
                    kind = "function"
                    names = re.findall(r"([~\w:]+)\s*\(", head)
                    name = names[0] if names else head[:40]
            stack.append((kind, code.count("\n", 0, i) + 1, name))
            head_start = i + 1
        elif c == "}":
            if stack:
                kind, first, name = stack.pop()
                if kind == "function":
                    lines = code.count("\n", 0, i) + 1 - first + 1
                    if lines > limit:
                        out.append((first, lines, name))
            head_start = i + 1
        elif c == ";":
            head_start = i + 1
    return out


def self_tests(known):
    """Each check on a case it must catch; the first that does not, or None."""
    if not upward_includes("estimation", '#include "run/job_run.h"\n', known):
        return "the upward include"
    cyclic = {"a.h": '#include "x/b.h"\n', "b.h": "", "b.cc": '#include "x/a.h"\n',
              "c.h": '#include "x/a.h"\n'}
    if module_cycles("x", cyclic) != [["a", "b"]]:
        return "the module cycle"
    if not internal_includes("x", "a.h", '#include "x/internal/b.h"\n') or \
            not internal_includes("y", "c.cc", '#include "x/internal/b.h"\n') or \
            internal_includes("x", "a.cc", '#include "x/internal/b.h"\n'):
        return "the internal headers"
    body = "namespace n {\nint F(int x) {\n" + "  x += 1;\n" * 130 + "  return x;\n}\n}\n"
    short = "namespace n {\nstruct S {\n  int G() const {\n    return 1;\n  }\n};\n}\n"
    if [f[2] for f in long_functions(body, MAX_FUNCTION_LINES)] != ["F"]:
        return "the long function"
    if long_functions(short, 3):
        return "a short function counted as long"
    return None


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--root", required=True)
    root = parser.parse_args().root
    known = set(LAYERS) | set(TOP)
    failed = self_tests(known)
    if failed:
        print(f"layering: the self-test found no problem in {failed}")
        return 1
    problems = []
    for entry in sorted(os.listdir(root)):
        path = os.path.join(root, entry)
        if not os.path.isdir(path) or entry.startswith(".") or entry.startswith("build"):
            continue
        has_code = any(f.endswith((".h", ".cc")) for f in os.listdir(path))
        if has_code and entry not in known:
            problems.append(f"{entry}/: C++ code in a folder that is no layer (tests/layering_test.py)")
    for folder in LAYERS:
        files = {}
        for sub in ("", "internal/"):
            path = os.path.join(root, folder, sub)
            if not os.path.isdir(path):
                continue
            for name in sorted(os.listdir(path)):
                if not name.endswith((".h", ".cc")):
                    continue
                with open(os.path.join(path, name), encoding="utf-8") as f:
                    files[sub + name] = f.read()
        for name, text in files.items():
            for line, target in upward_includes(folder, text, known):
                problems.append(f"{folder}/{name}:{line}: includes {target}/, a higher layer")
            for line, header in internal_includes(folder, name, text):
                problems.append(f"{folder}/{name}:{line}: includes {header}, internal to "
                                f"{header.split('/')[0]}/ (not for its public headers nor "
                                "other layers)")
            for first, lines, function in long_functions(text, MAX_FUNCTION_LINES):
                problems.append(f"{folder}/{name}:{first}: {function} is {lines} lines long "
                                f"(at most {MAX_FUNCTION_LINES}: a class with a method per step)")
        for cycle in module_cycles(folder, files):
            problems.append(f"{folder}/: the modules {', '.join(cycle)} include each other "
                            "(a cycle; move what they share into a module of its own)")
    for folder in ("apps", "python", "bench", "fuzz"):
        path = os.path.join(root, folder)
        for name in sorted(os.listdir(path)) if os.path.isdir(path) else []:
            if not name.endswith((".h", ".cc")):
                continue
            with open(os.path.join(path, name), encoding="utf-8") as f:
                for line, header in internal_includes(folder, name, f.read()):
                    problems.append(f"{folder}/{name}:{line}: includes {header}, internal to "
                                    f"{header.split('/')[0]}/")
    for p in problems:
        print(p)
    print(f"layering: {len(problems)} problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
