#!/usr/bin/env python3
"""Fail when a tracked file reads as a lab notebook instead of a reference.

History (which numbered session or round of work produced a figure, which
issue asked for it, which branch carried it) belongs in git and in one dated
line of CHANGELOG.md; a reference page states the method, the current figure
and the command that reproduces it. This check scans every file `git ls-files`
lists (or the files given on the command line) except CHANGELOG.md, and
prints
each offending line as `file:line: text` (exit 1), or nothing (exit 0).

Flagged, case-insensitively:
  - the word session or round (singular or plural) followed by a number:
    numbered rounds of work;
  - the word issue followed by a number, written plain, with # or with a
    hyphen, or a list of numbers: tracker numbers;
  - branch names of the project's history, but only beside the words branch,
    helper or worktree (or as a wt-<name> worktree path, not inside a sweep
    point's name): TriStore is also a module, bench and formal are also targets.

Usage: scripts/check-history.py [--root DIR] [FILE ...]
"""
import argparse
import os
import re
import subprocess
import sys

# Branches merged into main so far, and the ones open beside them (git log
# --merges; git branch -a). Matched only in a branch-ish context, see above.
BRANCH_NAMES = [
    "answer", "bench", "bench2", "bridge", "cocotb", "cppsim", "docs", "dp",
    "dram", "faults", "fmax", "fmt", "formal", "formal2", "formal3", "fp",
    "grid", "hls", "leaf128", "mem-model", "nori", "nori2", "norirtl", "pipe",
    "quant", "render", "report", "rust-wide", "sysctl", "sysfmax", "sysmem",
    "tristore", "wide",
]

_names = "|".join(sorted((re.escape(n) for n in BRANCH_NAMES), key=len, reverse=True))
_q = "[`'\"]?"
PATTERNS = [
    ("numbered round of work", re.compile(r"\b(?:sessions?|rounds?)\s+#?\d+", re.I)),
    ("issue number", re.compile(r"\bissues?[\s-]+#?\d+", re.I)),
    ("branch name", re.compile(
        rf"\b(?:branch(?:es)?|helpers?|worktrees?)\s+{_q}(?:{_names}){_q}(?![\w-])", re.I)),
    ("branch name", re.compile(
        rf"(?<![\w-]){_q}(?:{_names}){_q}\s+(?:branch|helper|worktree)\b", re.I)),
    # A worktree path, not the tail of a sweep point's name (4q-e8m23-e8m23-cons-wt-grid).
    ("branch name", re.compile(r"(?<![\w-])wt-[a-z0-9]", re.I)),
]

# CHANGELOG.md holds the history; this check and its spec hold the patterns.
EXEMPT = {"CHANGELOG.md"}


def tracked_files(root):
    out = subprocess.run(["git", "ls-files", "-z"], cwd=root, check=True,
                         stdout=subprocess.PIPE).stdout
    return [p for p in out.decode().split("\0") if p]


def scan(root, paths):
    hits = []
    for rel in paths:
        if rel in EXEMPT or os.path.basename(rel) == "CHANGELOG.md":
            continue
        full = os.path.join(root, rel)
        if not os.path.isfile(full):
            continue  # deleted in the work tree, or a submodule
        with open(full, "rb") as f:
            data = f.read()
        if b"\0" in data[:8192]:
            continue  # binary (images)
        for no, line in enumerate(data.decode("utf-8", "replace").splitlines(), 1):
            for what, rx in PATTERNS:
                m = rx.search(line)
                if m:
                    hits.append(f"{rel}:{no}: {what} '{m.group(0)}': {line.strip()[:160]}")
                    break
    return hits


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--root", default=".", help="repository to scan (default: .)")
    ap.add_argument("files", nargs="*", help="files relative to --root (default: git ls-files)")
    a = ap.parse_args()
    hits = scan(a.root, a.files or tracked_files(a.root))
    for h in hits:
        print(h)
    if hits:
        print(f"check-history: {len(hits)} line(s) cite history; say what is true now and put "
              "the history in CHANGELOG.md (one dated line) or the commit message", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
