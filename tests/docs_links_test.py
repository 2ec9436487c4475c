#!/usr/bin/python3
"""Every `configs/...` path (and every path into the other source folders:
sim/, fit/, fleet/, apps/, python/, tests/, scripts/, testdata/, …) and every
command-line flag (`--something`) named in README.md and docs/*.md exists;
every relative link resolves.

  tests/docs_links_test.py --root SOURCE_DIR --bin BUILD_DIR/bin [FILE.md ...]

- A path `configs/...` (or `fit/...`, `tests/...`, …) must exist in the source tree (a `*` in it is a glob
  that must match something; a trailing `/` names a folder).
- A flag must appear in the `--help` output of one of the apps
  (fit-params, fit-campaign, fit-fleet, simulate-axis, run from --bin; and
  the bench_* executables' google-benchmark flags, if built) or in
  a file under scripts/, examples/ or bench/, or be one of the few flags of external
  tools listed in EXTERNAL below (mpirun, srun, ctest, cmake).
- A relative markdown link [text](target) must name an existing file
  (PENDING lists pages another change is writing).

The generated tables (between `<!-- BEGIN generated: NAME -->` markers)
are not searched for paths and flags (they are tools' output); they must be what `scripts/docs-tables --check` renders from
docs/measurements.json: a figure typed into a table by hand fails.

Before checking the real files it checks itself: a scratch page naming a
bogus path, a bogus flag and a broken link must fail on all three, so the
test cannot pass by finding nothing. Exit 0 when all is well, 1 with one
line per problem otherwise. Python 3 standard library only.
"""
import argparse
import glob
import os
import re
import subprocess
import sys
import tempfile

APPS = ["fit-params", "fit-campaign", "fit-fleet", "simulate-axis"]
BENCHES = ["bench_rk4_step", "bench_fit", "bench_fleet"]  # their google-benchmark flags
FLAG_SOURCES = ["scripts", "examples", "bench"]
# Flags of tools that are not this project's, named in the docs with them.
EXTERNAL = {
    "--oversubscribe": "mpirun", "--allow-run-as-root": "mpirun", "--mpi": "srun",
    "--test-dir": "ctest", "--output-on-failure": "ctest",
    "--install": "cmake", "--prefix": "cmake", "--build": "cmake",
}
PENDING = set()  # docs not yet written

PATH_RE = re.compile(r"(?<![\w./-])(?:configs|sim|common|job|estimation|discovery|design|report|run|fleet|apps|python|tests|scripts|testdata|"
                     r"examples|bench|fuzz|cmake|docs)/[\w./*-]*")
FLAG_RE = re.compile(r"(?<![\w-])--[a-z][a-z0-9_-]*")
LINK_RE = re.compile(r"\]\(([^)\s]+)\)")


def known_flags(root, bin_dir):
    flags, problems = set(), []
    for app in APPS:
        exe = os.path.join(bin_dir, app)
        if not os.path.exists(exe):
            problems.append(f"{exe}: missing (build first)")
            continue
        proc = subprocess.run([exe, "--help"], capture_output=True, text=True,
                              stdin=subprocess.DEVNULL, timeout=60)
        flags.update(FLAG_RE.findall(proc.stdout + proc.stderr))
    for bench in BENCHES:  # optional: named in docs/performance.md
        exe = os.path.join(bin_dir, bench)
        if os.path.exists(exe):
            proc = subprocess.run([exe, "--help"], capture_output=True, text=True,
                                  stdin=subprocess.DEVNULL, timeout=60)
            flags.update(FLAG_RE.findall(proc.stdout + proc.stderr))
    for folder in FLAG_SOURCES:
        for path in glob.glob(os.path.join(root, folder, "**", "*"), recursive=True):
            if os.path.isfile(path):
                try:
                    with open(path, encoding="utf-8") as f:
                        flags.update(FLAG_RE.findall(f.read()))
                except (UnicodeDecodeError, OSError):
                    pass
    flags.update(EXTERNAL)
    return flags, problems


def check_file(md, root, flags):
    problems = []
    with open(md, encoding="utf-8") as f:
        text = f.read()
    # Generated tables are the tools' output (checked against
    # docs/measurements.json below; they quote e.g. other projects' paths):
    # blanked, keeping the line numbers.
    text = re.sub(r"(<!-- BEGIN generated: [\w-]+ -->)(.*?)(<!-- END generated -->)",
                  lambda m: m.group(1) + "\n" * m.group(2).count("\n") + m.group(3),
                  text, flags=re.S)
    name = os.path.relpath(md, root)
    for lineno, line in enumerate(text.splitlines(), 1):
        for path in PATH_RE.findall(line):
            path = path.rstrip(".,;:")
            if "*" in path:
                if not glob.glob(os.path.join(root, path)):
                    problems.append(f"{name}:{lineno}: {path}: matches nothing")
            elif os.path.normpath(path).split(os.sep)[0] == "build":
                continue  # an output the tools write (not in a fresh clone)
            elif not os.path.exists(os.path.join(root, path)) and path not in PENDING:
                problems.append(f"{name}:{lineno}: {path}: no such file or folder")
        for flag in FLAG_RE.findall(line):
            if flag not in flags:
                problems.append(f"{name}:{lineno}: {flag}: in no app's --help, "
                                "nor in scripts/, examples/ or bench/")
        for target in LINK_RE.findall(line):
            if re.match(r"^[a-z]+:", target) or target.startswith("#"):
                continue
            target = target.split("#", 1)[0]
            resolved = os.path.normpath(os.path.join(os.path.dirname(md), target))
            rel = os.path.relpath(resolved, root)
            if not os.path.exists(resolved) and rel not in PENDING:
                problems.append(f"{name}:{lineno}: link {target}: no such file")
    return problems


def self_test(root, flags):
    """The checker must find a bogus path, a bogus flag and a broken link."""
    with tempfile.TemporaryDirectory() as tmp:
        page = os.path.join(tmp, "bogus.md")
        with open(page, "w", encoding="utf-8") as f:
            f.write("Run `fit-params configs/jobs/no_such_job.yaml --no-such-flag`,\n"
                    "see [nowhere](no_such_page.md). Fine: `configs/jobs/x_axis_paper.yaml`.\n")
        found = check_file(page, root, flags)
    expected = ["configs/jobs/no_such_job.yaml", "--no-such-flag", "no_such_page.md"]
    missing = [e for e in expected if not any(e in p for p in found)]
    extra = [p for p in found if not any(e in p for e in expected)]
    return [f"self-test: the checker missed {m}" for m in missing] + \
           [f"self-test: a false alarm: {p}" for p in extra]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--root", required=True)
    ap.add_argument("--bin", required=True)
    ap.add_argument("files", nargs="*")
    args = ap.parse_args()
    root = os.path.abspath(args.root)
    flags, problems = known_flags(root, args.bin)
    problems += self_test(root, flags)
    files = args.files or [os.path.join(root, "README.md")] + sorted(
        glob.glob(os.path.join(root, "docs", "*.md")))
    checked = 0
    for md in files:
        problems += check_file(os.path.abspath(md), root, flags)
        checked += 1
    if not args.files:
        proc = subprocess.run([sys.executable, os.path.join(root, "scripts", "docs-tables"),
                               "--check"], capture_output=True, text=True, timeout=60)
        if proc.returncode != 0:
            problems.append("generated tables differ from docs/measurements.json "
                            "(run scripts/docs-tables): " + proc.stderr.strip())
    for p in problems:
        print(p)
    if problems:
        print(f"docs_links: {len(problems)} problem(s) in {checked} file(s)")
        return 1
    print(f"docs_links: {checked} file(s) checked, every configs/ path, flag and link exists")
    return 0


if __name__ == "__main__":
    sys.exit(main())
