#!/usr/bin/env python3
"""The layers point only downwards (docs/architecture.md).

Every `#include "<folder>/<file>.h"` in a library folder must name a folder
of the same or a lower layer: io < sim < common < job < estimation < discovery <
design < tune < report < run < fleet; apps/, python/ and bench/ sit on top and may
include any layer. CMake links static libraries whatever their includes
say, so this test is what keeps a cycle from coming back. It also checks
that every folder holding library code is in the list, and self-tests on a
made-up upward include first (so that it can fail).

    layering_test.py --root SOURCE_DIR
"""
import argparse
import os
import re
import sys

LAYERS = ["io", "sim", "common", "job", "estimation", "discovery", "design", "tune", "report",
          "run", "fleet"]
TOP = ["apps", "python", "bench", "fuzz", "tests"]
INCLUDE = re.compile(r'^\s*#\s*include\s+"([\w.-]+)/[\w./-]+"', re.M)


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


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--root", required=True)
    root = parser.parse_args().root
    known = set(LAYERS) | set(TOP)
    # Self-test: an estimation/ file that includes a run/ header is caught.
    if not upward_includes("estimation", '#include "run/job_run.h"\n', known):
        print("layering: the self-test found no upward include")
        return 1
    problems = []
    for entry in sorted(os.listdir(root)):
        path = os.path.join(root, entry)
        if not os.path.isdir(path) or entry.startswith(".") or entry == "build":
            continue
        has_code = any(f.endswith((".h", ".cc")) for f in os.listdir(path))
        if has_code and entry not in known:
            problems.append(f"{entry}/: C++ code in a folder that is no layer (tests/layering_test.py)")
    for folder in LAYERS:
        for name in sorted(os.listdir(os.path.join(root, folder))):
            if not name.endswith((".h", ".cc")):
                continue
            with open(os.path.join(root, folder, name), encoding="utf-8") as f:
                text = f.read()
            for line, target in upward_includes(folder, text, known):
                problems.append(f"{folder}/{name}:{line}: includes {target}/, a higher layer")
    for p in problems:
        print(p)
    print(f"layering: {len(problems)} problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
