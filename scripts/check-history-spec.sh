#!/usr/bin/env bash
# The history check's spec (part of `make test`, under a second): it must fail
# on a planted line that names a numbered session, name the file and line, and
# pass on a reference page and on a module that shares a branch's name
# (TriStore). The planted words are spliced from variables so that this file
# itself cites no history and needs no exemption.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
check="$here/check-history.py"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
git -C "$tmp" init -q

fail() { echo "check-history-spec: FAIL: $*"; exit 1; }

# A clean reference page, and names the check must not confuse with history.
cat > "$tmp/clean.md" <<'PAGE'
# Node store
TriStore serves the triangle records; `make bench` writes the table.
Rounding mode: round to nearest even, then conservative rounding.
The sweep point 4q-e8m23-e8m23-cons-wt-grid tests boxes in the node's grid.
PAGE
git -C "$tmp" add clean.md
python3 "$check" --root "$tmp" >/dev/null || fail "a clean page was flagged"

# Each planted line must be caught, with its file and line number.
plant() { # plant <line> <what>
  printf '# Page\n\n%s\n' "$1" > "$tmp/planted.md"
  git -C "$tmp" add planted.md
  if out=$(python3 "$check" --root "$tmp" 2>&1); then fail "$2 passed: '$1'"; fi
  grep -q '^planted.md:3: ' <<<"$out" || fail "$2: no 'planted.md:3:' in: $out"
}
S=session R=Round I=issue B=branch H=helper
plant "Measured in $S 3 on the loaded machine." "a numbered session"
plant "### $R 2" "a numbered-round heading"
plant "# Fmax estimate ($I 12)" "an issue number"
plant "the goals of $I #13 are met" "an issue number with #"
plant "written on $B \`tristore\` before the merge" "a branch name"
plant "the $H leaf128 found the bug" "a helper's branch"
W=wt
plant "built in ../$W-grid first" "a worktree path"

# CHANGELOG.md is where history goes: never flagged.
printf '# Changelog\n%s 3 and %s 7, %s `wide`\n' "$S" "$I" "$B" > "$tmp/CHANGELOG.md"
rm "$tmp/planted.md"; git -C "$tmp" rm -q --cached planted.md; git -C "$tmp" add CHANGELOG.md
python3 "$check" --root "$tmp" >/dev/null || fail "CHANGELOG.md was flagged"
echo "check-history-spec: passed (7 planted lines caught, clean page and CHANGELOG.md pass)"
