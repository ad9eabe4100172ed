#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Checks the documentation against the tree (ctest docs_check):

1. every relative Markdown link and image of README.md, config/README.md and docs/**/*.md points
   at a file or folder that exists, and a #anchor at a heading of the linked page;
2. every repository path those pages name in code (`config/...yaml`, `scripts/...sh`, ...)
   exists, so that a moved or deleted file is not left cited;
3. the installed-headers table of docs/plugins.md lists exactly the installed headers
   (VDBMAP_INSTALLED_HEADERS of libvdbmap/CMakeLists.txt, plus the generated Version.h).

Usage: check_docs.py --root SOURCE_DIR --installed a.h,core/b.h,...
Prints every problem with its file and line and exits 1 if there is one.
"""
import argparse
import os
import re
import sys

LINK = re.compile(r"!?\[[^\]]*\]\(([^()\s]+)(?:\s+\"[^\"]*\")?\)")
# A path into the tree with a file extension, as the pages cite them in code.
TREE_PATH = re.compile(
    r"(?<![\w./-])((?:config|scripts|bench|docs|examples|plugins|apps|libvdbmap|tests|cmake)"
    r"/[\w./-]*\.(?:yaml|sh|py|md|cpp|h|txt|cmake))(?![\w/-])")
HEADERS_BEGIN = "<!-- installed-headers: begin -->"
HEADERS_END = "<!-- installed-headers: end -->"


def pages(root):
    found = [os.path.join(root, "README.md"), os.path.join(root, "config", "README.md")]
    for dirpath, _, names in os.walk(os.path.join(root, "docs")):
        found += [os.path.join(dirpath, n) for n in sorted(names) if n.endswith(".md")]
    return [p for p in found if os.path.isfile(p)]


def slug(heading):
    """GitHub's anchor of a heading: lower case, punctuation dropped, spaces to hyphens."""
    text = re.sub(r"`|\*\*|\[([^\]]*)\]\([^)]*\)", r"\1", heading.strip()).lower()
    return re.sub(r"[^\w\- ]", "", text).replace(" ", "-")


def anchors(path, cache={}):
    if path not in cache:
        seen, result, fenced = {}, set(), False
        for line in open(path, encoding="utf-8"):
            if line.startswith("```"):
                fenced = not fenced
            m = re.match(r"#{1,6}\s+(.*?)\s*#*\s*$", line)
            if m and not fenced:
                base = slug(m.group(1))
                n = seen.get(base, 0)
                seen[base] = n + 1
                result.add(base if n == 0 else "%s-%d" % (base, n))
        cache[path] = result
    return cache[path]


def prose(line):
    """The line without its inline code spans (links inside code are not links)."""
    return re.sub(r"`[^`]*`", "", line)


def check_page(root, page, problems):
    where = os.path.relpath(page, root)
    fenced = False
    for number, line in enumerate(open(page, encoding="utf-8"), 1):
        if line.startswith("```"):
            fenced = not fenced
            continue
        for path in TREE_PATH.findall(line):
            if not os.path.exists(os.path.join(root, path)):
                problems.append("%s:%d: names %s, which does not exist" % (where, number, path))
        if fenced:
            continue
        for target in LINK.findall(prose(line)):
            if re.match(r"[a-z]+:", target):  # http:, https:, mailto:
                continue
            file_part, _, anchor = target.partition("#")
            linked = os.path.normpath(os.path.join(os.path.dirname(page), file_part)) \
                if file_part else page
            if not os.path.exists(linked):
                problems.append("%s:%d: link %s: no such file" % (where, number, target))
            elif anchor and linked.endswith(".md") and anchor not in anchors(linked):
                problems.append("%s:%d: link %s: no heading with that anchor in %s" %
                                (where, number, target, os.path.relpath(linked, root)))


def documented_headers(plugins_md, problems):
    text = open(plugins_md, encoding="utf-8").read()
    if HEADERS_BEGIN not in text or HEADERS_END not in text:
        problems.append("docs/plugins.md: no installed-headers table between %s and %s" %
                        (HEADERS_BEGIN, HEADERS_END))
        return set()
    table = text.split(HEADERS_BEGIN, 1)[1].split(HEADERS_END, 1)[0]
    headers = set()
    for row in table.splitlines():
        m = re.match(r"\|\s*`([\w/]+)`\s*\|([^|]*)\|", row)
        if not m:
            continue
        folder = "" if m.group(1) == "vdbmap/" else m.group(1)
        headers |= {folder + h for h in re.findall(r"`([\w]+\.h)`", m.group(2))}
    return headers


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--root", required=True)
    parser.add_argument("--installed", required=True, help="comma-separated, as in CMake")
    args = parser.parse_args()
    root = os.path.abspath(args.root)
    problems = []
    checked = pages(root)
    for page in checked:
        check_page(root, page, problems)

    installed = {h for h in args.installed.split(",") if h} | {"Version.h"}
    documented = documented_headers(os.path.join(root, "docs", "plugins.md"), problems)
    for h in sorted(installed - documented):
        problems.append("docs/plugins.md: installed header %s is missing from the table" % h)
    for h in sorted(documented - installed):
        problems.append("docs/plugins.md: the table lists %s, which is not installed" % h)

    for p in problems:
        print(p)
    if problems:
        return 1
    print("docs_check: %d pages, every link and path resolves; %d installed headers documented"
          % (len(checked), len(installed)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
