#!/usr/bin/env bash
# Bounded model checking of the small RtAccel configurations EmitFormal wrote
# into $1 (docs/formal.md). For each case in cases.txt: a wrapper holds reset
# in the first cycle, Yosys turns the design with its assertions and
# assumptions into an AIGER model, and ABC's bmc3 checks every assertion at
# every step up to the case's depth. Each property and the depth reached go
# to formal.log; on a failure each property is checked alone to name it.
# With a case list other than cases.txt (make formal-deep: cases-deep.txt)
# the log is formal-<list>.log.
# With a time limit (seconds per case, 0: none), a case the limit stops
# reports the steps it reached and does not fail.
# Usage: scripts/formal.sh <dir> [DEPTH override] [case list] [seconds per case]
set -euo pipefail
dir=$1; override=${2:-}; list=${3:-cases.txt}; secs=${4:-0}
. "$(dirname "$0")/formal-lib.sh"
if [ "$list" = cases.txt ]; then log=$dir/formal.log; else log=$dir/formal-${list%.txt}.log; fi
: > "$log"
status=0
while read -r name depth bound; do
  [ -n "$override" ] && depth=$override
  formal_wrap "$dir" "$name"
  start=$(date +%s)
  formal_aig "$dir" "$name" "$dir/formal_$name.sv" "$dir/formal_$name.aig"
  verdict=$(formal_bmc "$dir/formal_$name.aig" "$depth" "$dir/bmc_$name.log" "$secs")
  took=$(( $(date +%s) - start ))
  asked=$depth
  if [ "$verdict" = pass ]; then result="PASS (no assertion fails in steps 1..$depth)"
  elif [ "${verdict#limit:}" != "$verdict" ]; then
    depth=${verdict#limit:}; verdict=pass
    result="NO VERDICT past step $depth: the $secs s limit stopped it; no assertion fails in steps 1..$depth"
  else result="FAIL (an assertion fails at step $verdict)"; status=1; fi
  {
    echo "case $name: bounded model check (ABC bmc3) to depth $asked (step 1 is reset), $took s: $result"
    echo "  responseBound = $bound cycles"
    while read -r prop; do
      note=""
      # A ray can only overstay the bound after `bound` cycles: below that depth the check is empty.
      case $prop in *bounded_response*)
        if [ "$depth" -le "$bound" ]; then note=" (VACUOUS: depth $depth <= responseBound $bound, not proven)"
        else note=" (every ray that entered by step $((depth - bound)) is followed until it leaves)"; fi;; esac
      if [ "$verdict" = pass ]; then echo "  $prop: PASS to depth $depth$note"
      else
        formal_aig "$dir" "$name" "$dir/formal_$name.sv" "$dir/formal_${name}_$prop.aig" "$prop"
        one=$(formal_bmc "$dir/formal_${name}_$prop.aig" "$depth" "$dir/bmc_${name}_$prop.log" "$secs")
        if [ "$one" = pass ]; then echo "  $prop: PASS to depth $depth$note"
        elif [ "${one#limit:}" != "$one" ]; then echo "  $prop: no failure to depth ${one#limit:} (the time limit stopped it)"
        else echo "  $prop: FAIL at step $one"; fi
      fi
    done < "$dir/formal_$name.props"
  } | tee -a "$log"
done < "$dir/$list"
exit $status
