#!/usr/bin/env python3
"""Fails when a relative link in the documentation does not resolve.

  check_links.py --root SOURCE_DIR

Checks README.md, every docs/**/*.md and the READMEs under reference_inputs/ and tests/: each
[text](target) and ![alt](target) outside code, where target is not a URL, must name an existing
file or directory relative to the page, and a #fragment must be a heading of the target page
(GitHub's anchors: lower case, punctuation dropped, spaces as hyphens, -1, -2 ... for repeats).
"""
import argparse
import re
import sys
from pathlib import Path

LINK = re.compile(r"!?\[(?:[^\]\[]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
HEADING = re.compile(r"^ {0,3}(#{1,6})\s+(.*?)\s*#*\s*$")
FENCE = re.compile(r"^ {0,3}(```|~~~)")
CODE_SPAN = re.compile(r"(`+)(.+?)\1")


def pages(root):
    found = [root / "README.md"] + sorted((root / "docs").rglob("*.md"))
    for d in ("reference_inputs", "tests"):
        found += sorted((root / d).rglob("README.md"))
    return [p for p in found if p.is_file()]


def prose_lines(path):
    """(line number, text, text with inline code removed) outside fenced code blocks."""
    fenced = False
    for no, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        if FENCE.match(line):
            fenced = not fenced
            continue
        if not fenced:
            yield no, line, CODE_SPAN.sub("", line)


def slug(heading):
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", heading)  # a link in a heading keeps its text
    text = text.strip().lower().replace("`", "")
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors(path, cache={}):
    if path not in cache:
        seen, out = {}, set()
        for _, line, _ in prose_lines(path):
            m = HEADING.match(line)
            if not m:
                continue
            base = slug(m.group(2))
            n = seen.get(base, 0)
            seen[base] = n + 1
            out.add(base if n == 0 else f"{base}-{n}")
        cache[path] = out
    return cache[path]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--root", required=True, help="repository root")
    root = Path(ap.parse_args().root).resolve()
    problems, links = [], 0
    files = pages(root)
    for page in files:
        for no, _, line in prose_lines(page):
            for target in LINK.findall(line):
                if re.match(r"^[a-z][a-z0-9+.-]*:", target, re.I):  # https:, mailto:, ...
                    continue
                links += 1
                where = f"{page.relative_to(root)}:{no}"
                file_part, _, fragment = target.partition("#")
                dest = (page.parent / file_part).resolve() if file_part else page
                if not dest.exists():
                    problems.append(f"{where}: {target}: no such file")
                elif fragment and dest.suffix == ".md" and fragment not in anchors(dest):
                    problems.append(f"{where}: {target}: no heading #{fragment} in {dest.relative_to(root)}")
    for p in problems:
        print(p)
    print(f"{links} relative links in {len(files)} pages checked, {len(problems)} broken")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
