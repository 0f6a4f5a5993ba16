#!/usr/bin/env bash
# The system's units alone (docs/formal.md, "System units"; FormalSystemUnits.scala), run by
# `make formal-system-units` after the emission; not part of make test.
#  1. BMC (bmc3) of each unit to its depth in system-units.txt (scripts/formal.sh; 8 steps past the
#     unit's derived bound where the frames allow), each stopped after the BMC time limit (the log
#     then gives the steps reached), log formal-system-units.log.
#  2. pdr (IC3) on each unit, time-limited: "proved" is for all time (every reachable state), bounded
#     response included (an age counter makes it a safety property); appended to the same log.
# Usage: scripts/formal-system-units.sh <dir> [pdr seconds per unit] [BMC seconds per unit]
set -euo pipefail
dir=$1; secs=${2:-120}; bmcsecs=${3:-600}
. "$(dirname "$0")/formal-lib.sh"
status=0
"$(dirname "$0")/formal.sh" "$dir" "" system-units.txt "$bmcsecs" || status=1
log=$dir/formal-system-units.log
while read -r name depth bound; do
  echo "case $name: pdr (unbounded), every property above: $(tr '\n' ' ' < "$dir/formal_$name.props")" | tee -a "$log"
  engine "$dir/formal_$name.aig" pdr "pdr -T $secs"
  # A counterexample fails the target; "no verdict" (the time limit) is reported, not failed (ReadEngine: docs/formal.md).
  if tail -1 "$log" | grep -q counterexample; then status=1; fi
done < "$dir/system-units.txt"
exit $status
