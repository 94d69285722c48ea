#!/usr/bin/env python3
"""Checks of the user documentation: README.md, docs/*.md and the headers of
scenes/*.yml.

  check_docs.py ROOT         check the repository at ROOT; exit 1 naming each
                             problem (file:line: what)
  check_docs.py --self-test  check that each rule below finds a planted fault

Rules: every relative Markdown link resolves to a file of the repository and,
for a .md file with #anchor, to one of its headings (GitHub's anchor rule:
lower case, punctuation but '-' and '_' dropped, spaces to '-'); nothing
points outside the repository (a link leaving ROOT, or the text
'shared/spec'); no issue numbers ('issue 12', 'issues 12-14'); the README
stays at most README_MAX_LINES lines (a newcomer's page; references go to
docs/)."""
import glob
import os
import re
import sys
import tempfile

README_MAX_LINES = 250
ISSUE = re.compile(r"\bissues? +#?[0-9]+", re.IGNORECASE)
LINK = re.compile(r"\]\(([^)\s]+)\)")


def anchors(path):
    out = set()
    fence = False
    with open(path, encoding="utf-8") as fp:
        for line in fp:
            if line.startswith("```"):
                fence = not fence
            m = None if fence else re.match(r"#{1,6} +(.*)", line)
            if m:
                a = re.sub(r"[^\w\- ]", "", m.group(1).strip().lower())
                out.add(a.replace(" ", "-"))
    return out


def check(root):
    root = os.path.realpath(root)
    problems = []
    pages = [os.path.join(root, "README.md")] + sorted(glob.glob(os.path.join(root, "docs", "*.md")))
    for page in pages:
        rel = os.path.relpath(page, root)
        with open(page, encoding="utf-8") as fp:
            lines = fp.read().split("\n")
        if rel == "README.md" and len(lines) - 1 > README_MAX_LINES:
            problems.append("%s: %d lines, more than %d (move reference text to docs/)"
                            % (rel, len(lines) - 1, README_MAX_LINES))
        for n, line in enumerate(lines, 1):
            where = "%s:%d" % (rel, n)
            if "shared/spec" in line:
                problems.append("%s: points outside the repository (shared/spec)" % where)
            m = ISSUE.search(line)
            if m:
                problems.append("%s: an issue number in user documentation: %r" % (where, m.group(0)))
            for m in LINK.finditer(line):
                target = m.group(1)
                if re.match(r"[a-z]+:", target):
                    continue
                path, _, anchor = target.partition("#")
                dest = os.path.realpath(os.path.join(os.path.dirname(page), path)) if path else page
                if not (dest == root or dest.startswith(root + os.sep)):
                    problems.append("%s: link %s points outside the repository" % (where, target))
                elif not os.path.exists(dest):
                    problems.append("%s: link %s: no such file" % (where, target))
                elif anchor and dest.endswith(".md") and anchor not in anchors(dest):
                    problems.append("%s: link %s: no heading with anchor #%s in %s"
                                    % (where, target, anchor, os.path.relpath(dest, root)))
    for scene in sorted(glob.glob(os.path.join(root, "scenes", "*.yml"))):
        rel = os.path.relpath(scene, root)
        with open(scene, encoding="utf-8") as fp:
            for n, line in enumerate(fp, 1):
                if not line.startswith("#"):
                    continue
                m = ISSUE.search(line)
                if m:
                    problems.append("%s:%d: an issue number in a scene's header: %r"
                                    % (rel, n, m.group(0)))
    return problems


def self_test():
    """Each rule finds its planted fault, and a clean tree passes."""
    faults = {
        "link to a missing file": ("README.md", "[x](docs/nothing.md)\n"),
        "missing anchor": ("README.md", "[x](docs/a.md#no-such-heading)\n"),
        "link outside": ("README.md", "[x](../outside.md)\n"),
        "shared/spec": ("docs/a.md", "# A\n\nsee `../shared/spec/paper.md`\n"),
        "issue number": ("docs/a.md", "# A\n\nas issue 12 asked\n"),
        "issue in a scene": ("scenes/s.yml", "# a scene (issue 13)\n---\nmetric: {m: 1}\n"),
        "long README": ("README.md", "line\n" * (README_MAX_LINES + 1)),
    }
    clean = {"README.md": "# T\n\n[a](docs/a.md#a-b) [top](#t)\n",
             "docs/a.md": "# A b\n\n[back](../README.md)\n",
             "scenes/s.yml": "# a scene\n---\nmetric: {m: 1}\n",
             "outside.md": ""}
    failed = 0
    for name, fault in [("clean", None)] + list(faults.items()):
        with tempfile.TemporaryDirectory() as d:
            repo = os.path.join(d, "repo")
            files = dict(clean)
            if fault:
                files[fault[0]] = fault[1]
            for rel, text in files.items():
                p = os.path.join(d if rel == "outside.md" else repo, rel)
                os.makedirs(os.path.dirname(p), exist_ok=True)
                with open(p, "w", encoding="utf-8") as fp:
                    fp.write(text)
            found = check(repo)
            ok = (not found) if fault is None else bool(found)
            print("self-test %-24s %s %s" % (name, "ok " if ok else "FAILED", found))
            failed += not ok
    return failed


if __name__ == "__main__":
    if sys.argv[1:] == ["--self-test"]:
        sys.exit(1 if self_test() else 0)
    if len(sys.argv) != 2:
        sys.exit("usage: check_docs.py ROOT | --self-test")
    found = check(sys.argv[1])
    for p in found:
        print(p)
    print("docs: %d problem(s)" % len(found))
    sys.exit(1 if found else 0)
