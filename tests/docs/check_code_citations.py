#!/usr/bin/env python3
"""The code cites the reference pages, not the notebook or the issues.

  check_code_citations.py SOURCE_DIR

Every source file of the libraries, the program and the tests (*.cpp, *.hpp, *.py, *.sh, *.tpl,
CMakeLists.txt), key help strings included, names no dated notebook page (docs/notebook/, a page
named by its date) and no "issue N": a reader of the code or of `ibvalve keys` is sent to docs/'s
guide and reference pages, which say what holds now. Prints each citation with its file and line;
exits 1 when there is one.
"""
import pathlib
import re
import sys

FOLDERS = ["app", "base", "io", "fluid", "ib", "fe", "fibers", "materials", "windkessel", "circulation",
           "hemodynamics", "tests", "scripts", "bench"]
SUFFIXES = {".cpp", ".hpp", ".py", ".sh", ".tpl", ".in", ".cmake"}
CITATION = re.compile(r"docs/notebook/|[\w-]+-\d{4}-\d{2}-\d{2}\.md|\bissue \d+|\bissue #\d+")


def main():
    root = pathlib.Path(sys.argv[1]).resolve()
    found = []
    for folder in FOLDERS:
        for path in sorted((root / folder).rglob("*")):
            if not path.is_file() or not (path.suffix in SUFFIXES or path.name == "CMakeLists.txt"):
                continue
            if path == pathlib.Path(__file__).resolve():
                continue
            for number, line in enumerate(path.read_text(errors="replace").splitlines(), start=1):
                if CITATION.search(line):
                    found.append(f"{path.relative_to(root)}:{number}: {line.strip()}")
    for line in found:
        print(line)
    if found:
        print(f"FAIL: {len(found)} lines of code cite the notebook or an issue (cite docs/'s reference pages)")
        sys.exit(1)
    print("PASS: no line of code cites the notebook or an issue")


if __name__ == "__main__":
    main()
