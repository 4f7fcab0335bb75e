#!/usr/bin/env python3
"""Compiles, for diagnostics only (-fsyntax-only), every translation unit of a configured build
tree that the tree's last build did not compile, with the tree's own compiler and flags.

scripts/test.sh builds only the fuzz targets in its clang tree (the modules they link), to keep CI
short; this runs clang's front end over the rest of the product (renderer, viewer, command line),
so that clang's warnings, errors under -Werror, are still seen in every file, at a fraction of a
full build's cost (no optimisation, no code generation, no sanitizer instrumentation).

    scripts/syntax_check.py BUILD_DIR [--jobs N] [--exclude SUBSTRING ...]

BUILD_DIR must have been configured with CMAKE_EXPORT_COMPILE_COMMANDS=ON. A unit counts as
compiled when its object file exists. Exit status 1 when any unit fails, with its diagnostics.
"""
import argparse
import concurrent.futures
import json
import os
import shlex
import subprocess
import sys


def syntax_only(entry):
    """The entry's command without its output and with -fsyntax-only."""
    args = entry["arguments"] if "arguments" in entry else shlex.split(entry["command"])
    out = []
    skip = False
    for arg in args:
        if skip:
            skip = False
            continue
        if arg in ("-o", "-MF", "-MT", "-MQ"):
            skip = True
            continue
        if arg in ("-MD", "-MMD"):
            continue
        out.append(arg)
    # ccache (a compiler launcher) would cache nothing useful here.
    if out and os.path.basename(out[0]) == "ccache":
        out = out[1:]
    return out + ["-fsyntax-only"]


def object_of(entry):
    args = entry["arguments"] if "arguments" in entry else shlex.split(entry["command"])
    for i, arg in enumerate(args[:-1]):
        if arg == "-o":
            return os.path.join(entry["directory"], args[i + 1])
    return None


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("build_dir")
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--exclude", action="append", default=[],
                        help="skip files whose path contains this")
    options = parser.parse_args()
    path = os.path.join(options.build_dir, "compile_commands.json")
    try:
        with open(path, encoding="utf-8") as f:
            entries = json.load(f)
    except OSError as error:
        print(f"syntax_check: cannot read {path}: {error} (configure with "
              "-DCMAKE_EXPORT_COMPILE_COMMANDS=ON)", file=sys.stderr)
        return 2
    todo = []
    for entry in entries:
        if any(part in entry["file"] for part in options.exclude):
            continue
        obj = object_of(entry)
        if obj and os.path.exists(obj):
            continue
        todo.append(entry)

    def run(entry):
        result = subprocess.run(syntax_only(entry), cwd=entry["directory"],
                                capture_output=True, text=True)
        return entry["file"], result.returncode, result.stdout + result.stderr

    failed = 0
    with concurrent.futures.ThreadPoolExecutor(max_workers=options.jobs) as pool:
        for file, code, output in pool.map(run, todo):
            if code != 0 or output.strip():
                print(f"---- {file}")
                print(output.rstrip())
            if code != 0:
                failed += 1
    print(f"syntax_check: {len(todo)} files checked, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
