#!/usr/bin/env bash
# Bounded model checking of the small RtAccel configurations EmitFormal wrote
# into $1 (docs/formal.md). For each case in cases.txt: a wrapper holds reset
# in the first cycle, Yosys reads the design with its assertions and
# assumptions, and its SAT engine checks every assertion at every step up to
# the case's depth. Each property and the depth reached go to formal.log.
# Usage: scripts/formal.sh <dir> [DEPTH override]
set -euo pipefail
dir=$1; override=${2:-}
log=$dir/formal.log
: > "$log"
status=0
while read -r name depth bound; do
  [ -n "$override" ] && depth=$override
  top=FormalTop_$name
  cat > "$dir/wrap_$name.sv" <<WRAP
module formal_$name(input clock);
  reg init = 1'b1;  // reset in the first cycle only
  always @(posedge clock) init <= 1'b0;
  $top top(.clock(clock), .reset(init));
endmodule
WRAP
  start=$(date +%s)
  if yosys -q -l "$dir/yosys_$name.log" -p "read_verilog -formal -sv $dir/FormalAnySeq.v $dir/formal_$name.sv $dir/wrap_$name.sv;
      prep -flatten -top formal_$name; memory_map; opt -fast; async2sync; dffunmap;
      sat -seq $depth -prove-asserts -set-assumes -verify -show-public -dump_vcd $dir/cex_$name.vcd" >/dev/null 2>&1; then
    result="PASS (no assertion fails in steps 1..$depth)"
  else
    result="FAIL"; status=1
  fi
  secs=$(( $(date +%s) - start ))
  {
    echo "case $name: bounded model check to depth $depth (cycle 1 is reset), $secs s: $result"
    echo "  responseBound = $bound cycles"
    while read -r prop; do
      note=""
      # A ray can only overstay the bound after `bound` cycles: below that depth the check is empty.
      case $prop in bounded_response*) [ "$depth" -le "$bound" ] && note=" (VACUOUS: depth $depth <= responseBound $bound, not proven)";; esac
      echo "  $prop: ${result%% *} to depth $depth$note"
    done < "$dir/formal_$name.props"
    if [ "$result" = FAIL ]; then
      grep -E "failed|Assert|assert.*\b1'0\b" "$dir/yosys_$name.log" | grep -v "Import proof" | tail -5 | sed 's/^/  /'
      echo "  counterexample: $dir/cex_$name.vcd"
    fi
  } | tee -a "$log"
done < "$dir/cases.txt"
exit $status
