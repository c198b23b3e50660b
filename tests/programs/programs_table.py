#!/usr/bin/env python3
"""The table of docs/programs.md, made from each program's own --help.

Usage: programs_table.py SOURCE_DIR --write DOC NAME=PATH...  replaces the table in DOC
       programs_table.py SOURCE_DIR --check DOC NAME=PATH...  exit 1 when a program's row in DOC
                                                              differs from what its --help says
(CMake: the target programs_doc and the test docs.programs_table pass every program built.)

Each row: the program, what it does (its help's description before "Exit status"), its
options (the flags its help lists; Google Benchmark's --benchmark_* for the benchmark
programs) and its exit statuses (the description's "Exit status: ..."). Paths in the help
are shown relative to SOURCE_DIR. The check compares only the programs given, so a build
without some of them checks the rest.
"""
import re
import subprocess
import sys

HEAD = ("| program | what it does | options | exit status |\n"
        "|---|---|---|---|\n")


def row(source, name, path):
    help_text = subprocess.run([path, "--help"], capture_output=True, text=True, timeout=60).stdout
    help_text = help_text.replace(source, ".")
    if "--benchmark_" in help_text:  # Google Benchmark: our line first, then its usage
        intro, _, usage = help_text.partition("benchmark [")
        description = " ".join(intro.split()).split(": ", 1)[1]
        options = sorted(set(re.findall(r"--benchmark_[a-z_]+", usage)))
    else:
        description = " ".join(help_text.split("Usage:")[0].split())
        description = re.sub(r"^[a-z_]+: ", "", description)
        options = []
        for line in help_text.split("Usage:")[1].splitlines():
            m = re.match(r"^  (-\w,)?(--[\w-]+|[A-Z]+)\b", line)
            if m and m.group(2) != "--help":
                options.append(m.group(2))
    what, _, status = description.partition("Exit status: ")
    what = what.strip().rstrip(".")
    status = status.strip().rstrip(".") or "-"
    opts = ", ".join(f"`{o}`" for o in options) if options else "none"
    return f"| `{name}` | {what} | {opts} | {status} |\n"


def main():
    args = sys.argv[1:]
    if len(args) < 2:
        print(__doc__)
        return 2
    source = args.pop(0)
    if len(args) < 3 or args[0] not in ("--write", "--check"):
        print(__doc__)
        return 2
    mode, doc, args = args[0], args[1], args[2:]
    rows = {}
    for a in args:
        name, _, path = a.partition("=")
        rows[name] = row(source, name, path)
    text = open(doc, encoding="utf-8").read()
    if mode == "--write":  # the table replaces the one between the heading and the next blank line
        start = text.index(HEAD)
        end = text.find("\n\n", start)
        end = len(text) if end < 0 else end + 1
        text = text[:start] + HEAD + "".join(rows[n] for n in sorted(rows)) + text[end:]
        open(doc, "w", encoding="utf-8").write(text)
        print(f"{doc}: {len(rows)} programs")
        return 0
    have = {m.group(1): m.group(0) + "\n"
            for m in re.finditer(r"^\| `([\w]+)` \|.*$", text, re.M)}
    stale = [n for n in sorted(rows) if have.get(n) != rows[n]]
    for n in stale:
        print(f"{doc}: the row of {n} is not what its --help says:\n  doc:  {have.get(n, '(none)').strip()}\n"
              f"  help: {rows[n].strip()}")
    if stale:
        print("regenerate it: the command at the top of " + doc)
        return 1
    print(f"{doc}: the rows of all {len(rows)} programs match their --help")
    return 0


if __name__ == "__main__":
    sys.exit(main())
