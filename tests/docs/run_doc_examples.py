#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Runs the shell examples of the user docs, so they stay true.

A ```sh block is run when the line before its fence is a marker such as

    <!-- test: exit 1; creates out/tutorial/compare/compare.json, out/tutorial/x.ply -->

("exit N" defaults to 0; "creates" lists files that must exist afterwards, relative to the
directory the examples run in). The marked blocks of each document run in order, in one fresh
directory holding a link to the repository's data/, with the build's `morphmill` first on PATH,
each under `bash -e -o pipefail`. Unmarked blocks (installing, `make demo`) are not run.

Usage: run_doc_examples.py MORPHMILL_BINARY REPOSITORY DOC.md [DOC.md ...]
"""
import os
import re
import subprocess
import sys
import tempfile
import time

MARKER = re.compile(r"^<!--\s*test:?(.*?)-->\s*$")
# Seconds each example may take; a sanitized build sets more (tests/CMakeLists.txt).
TIMEOUT_SECONDS = float(os.environ.get("MORPHMILL_DOC_EXAMPLE_SECONDS", "120"))


def marked_blocks(path):
    """(line number, expected exit code, files to exist, script) of every marked ```sh block."""
    lines = open(path, encoding="utf-8").read().split("\n")
    blocks = []
    i = 0
    while i < len(lines):
        marker = MARKER.match(lines[i].strip())
        if marker and i + 1 < len(lines) and lines[i + 1].strip() in ("```sh", "```bash"):
            expect_exit, creates = 0, []
            for part in (p.strip() for p in marker.group(1).split(";")):
                if part.startswith("exit"):
                    expect_exit = int(part.split()[1])
                elif part.startswith("creates"):
                    creates = [f.strip() for f in part[len("creates"):].split(",") if f.strip()]
                elif part:
                    raise SystemExit(f"{path}:{i + 1}: unknown marker part '{part}'")
            end = i + 2
            while end < len(lines) and lines[end].strip() != "```":
                end += 1
            if end == len(lines):
                raise SystemExit(f"{path}:{i + 2}: the ```sh block never closes")
            blocks.append((i + 2, expect_exit, creates, "\n".join(lines[i + 2:end]) + "\n"))
            i = end
        i += 1
    return blocks


def main():
    if len(sys.argv) < 4:
        raise SystemExit(__doc__)
    binary, repository, documents = os.path.abspath(sys.argv[1]), sys.argv[2], sys.argv[3:]
    env = dict(os.environ)
    env["PATH"] = os.path.dirname(binary) + os.pathsep + env.get("PATH", "")
    failures, count = [], 0
    for document in documents:
        path = os.path.join(repository, document)
        blocks = marked_blocks(path)
        if not blocks:
            failures.append(f"{document}: no marked examples (a marker line '<!-- test -->' before a ```sh fence)")
        with tempfile.TemporaryDirectory(prefix="morphmill_doc_") as work:
            os.symlink(os.path.join(os.path.abspath(repository), "data"), os.path.join(work, "data"))
            for line, expect_exit, creates, script in blocks:
                count += 1
                start = time.monotonic()
                try:
                    run = subprocess.run(["bash", "-e", "-o", "pipefail", "-c", script], cwd=work, env=env,
                                         capture_output=True, text=True, timeout=TIMEOUT_SECONDS)
                    code, output = run.returncode, run.stdout + run.stderr
                except subprocess.TimeoutExpired:
                    code, output = None, f"did not finish within {TIMEOUT_SECONDS:g} s"
                seconds = time.monotonic() - start
                where = f"{document}:{line}"
                print(f"{where}: exit {code} in {seconds:.1f} s")
                if code != expect_exit:
                    failures.append(f"{where}: exit {code}, the doc expects {expect_exit}\n{script}{output}")
                    continue
                for name in creates:
                    if not os.path.isfile(os.path.join(work, name)) or os.path.getsize(os.path.join(work, name)) == 0:
                        failures.append(f"{where}: '{name}' was not written\n{script}{output}")
    for failure in failures:
        print("FAILED " + failure, file=sys.stderr)
    print(f"{count} example(s) run, {len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
