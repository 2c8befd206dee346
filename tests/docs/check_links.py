#!/usr/bin/env python3
"""Every relative link of the documentation resolves.

  check_links.py SOURCE_DIR

Reads README.md, every page under docs/ and every README.md under examples/, bench/ and tests/, and
checks:
- each Markdown link [text](target) that is not a URL: the file or folder exists, relative to the
  page; a #fragment names a heading of the target page (GitHub's anchors: lower case, punctuation but
  - and _ dropped, spaces as -);
- each page named in the text as docs/NAME.md (how the pages cite each other): the file exists,
  relative to the repository.
Prints every broken link with its page and line; exits 1 when there is one.
"""
import pathlib
import re
import sys

LINK = re.compile(r"(?<!!)\[[^\]]*\]\(([^)\s]+)\)")
IMAGE = re.compile(r"!\[[^\]]*\]\(([^)\s]+)\)")
CITED = re.compile(r"(?<![\w/.-])(docs/[\w./-]+?\.md)\b")


def anchors(page):
    found = set()
    for line in page.read_text().splitlines():
        if line.startswith("#"):
            title = line.lstrip("#").strip().lower()
            slug = re.sub(r"[^\w\- ]", "", title).replace(" ", "-")
            found.add(slug)
    return found


def pages(root):
    yield root / "README.md"
    yield from sorted((root / "docs").rglob("*.md"))
    for folder in ("examples", "bench", "tests"):
        yield from sorted((root / folder).rglob("README.md"))


def main():
    root = pathlib.Path(sys.argv[1]).resolve()
    broken, links = [], 0
    for page in pages(root):
        if "/runs/" in str(page.relative_to(root)):
            continue
        in_code = False
        for number, line in enumerate(page.read_text().splitlines(), start=1):
            if line.lstrip().startswith("```"):
                in_code = not in_code
            if in_code:
                continue
            where = f"{page.relative_to(root)}:{number}"
            for target in LINK.findall(line) + IMAGE.findall(line):
                if re.match(r"^[a-z]+:", target):
                    continue
                links += 1
                path, _, fragment = target.partition("#")
                resolved = (page.parent / path).resolve() if path else page
                if not resolved.exists():
                    broken.append(f"{where}: {target}: no such file")
                elif fragment and resolved.is_file() and fragment not in anchors(resolved):
                    broken.append(f"{where}: {target}: no heading #{fragment} in {resolved.relative_to(root)}")
            for cited in CITED.findall(line):
                links += 1
                if not (root / cited).exists():
                    broken.append(f"{where}: {cited}: no such page")
    for line in broken:
        print(line)
    if broken:
        print(f"FAIL: {len(broken)} of {links} links do not resolve")
        sys.exit(1)
    print(f"PASS: {links} links resolve")


if __name__ == "__main__":
    main()
