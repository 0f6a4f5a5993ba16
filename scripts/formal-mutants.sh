#!/usr/bin/env bash
# Breaks the emitted n2 design on purpose, one way at a time, and checks that
# the bounded model check catches each break with the property meant to catch
# it (docs/formal.md). Each mutant is a sed edit of a scratch copy of
# formal_n2.sv; the original is untouched. For each expected property the
# other assertions are removed and an incremental BMC (Yosys `sat
# -tempinduct-baseonly`) finds the shortest counterexample.
# Usage: scripts/formal-mutants.sh <dir> <depth>   (after scripts/formal.sh)
set -euo pipefail
dir=$1; depth=$2
. "$(dirname "$0")/formal-lib.sh"
formal_wrap "$dir" n2
log=$dir/mutants.log
: > "$log"
status=0
mutant() { # name, what it breaks, sed expression, a text the edit must find, expected properties...
  local name=$1 what=$2 expr=$3 must=$4; shift 4
  local sv=$dir/mutant_$name.sv
  grep -qF -- "$must" "$dir/formal_n2.sv" || { echo "mutant $name: '$must' not in formal_n2.sv (update the mutant)" | tee -a "$log"; status=1; return; }
  sed -e "$expr" "$dir/formal_n2.sv" > "$sv"
  if cmp -s "$sv" "$dir/formal_n2.sv"; then echo "mutant $name: sed changed nothing" | tee -a "$log"; status=1; return; fi
  echo "mutant $name: $what" | tee -a "$log"
  for prop in "$@"; do
    local start=$(date +%s) step
    formal_aig "$dir" n2 "$sv" "$dir/mutant_${name}_$prop.aig" "$prop"
    step=$(formal_bmc "$dir/mutant_${name}_$prop.aig" "$depth" "$dir/mutant_${name}_$prop.log")
    if [ "$step" != pass ] && [ "$step" != error ]; then
      echo "  $prop: CAUGHT, shortest counterexample $step steps (step 1 is reset), $(( $(date +%s) - start )) s" | tee -a "$log"
    else
      echo "  $prop: NOT CAUGHT within $depth steps ($step)" | tee -a "$log"; status=1
    fi
  done
}
mutant fresh_forever "the free list hands out fresh IDs forever, so an ID in flight is issued again" \
  "s/wire       haveFresh = freshReg != 2'h2;/wire       haveFresh = 1'b1;/" "wire       haveFresh = freshReg != 2'h2;" \
  id_allocated_once_1 exactly_once_1
mutant free_unfired "an ID is freed while its hit still waits for the host, so the hit is emitted twice" \
  "s/(io_hits_ready & _trav_io_done_valid)/(_trav_io_done_valid)/" "(io_hits_ready & _trav_io_done_valid)" \
  id_freed_once_1 exactly_once_1
mutant init_queue_one "InitTraversal's queue holds one ray, not numRayIds: a prepared ray can find it full" \
  "/^module Queue2_PreparedEntry/,/^endmodule/{s/assign io_enq_ready = ~full;/assign io_enq_ready = empty;/;s/wire       do_enq = ~full \\& io_enq_valid;/wire       do_enq = empty \\& io_enq_valid;/}" \
  "module Queue2_PreparedEntry" no_overflow_init_1
# Not a break: an assertion that no ray ever comes back from a leaf. Its
# shortest counterexample is the first step at which a leaf round trip (box
# test, leaf job, triangle fetches and tests, return to TraversalControl) lies
# inside the checked depth, so the log shows what the depth covers.
mutant reach_leaf_exit "(probe) no ray ever returns from a leaf: fails at the first step a leaf round trip can end" \
  "s/^      if (~reset \& _init_io_broken) begin/      if (~reset \& _leaf_io_out_valid) begin reach_leaf_exit_1: assert(1'b0); end\n&/" \
  "      if (~reset & _init_io_broken) begin" reach_leaf_exit_1
# Not a break either: bounded_response with the bound cut from 80 to 16
# cycles. It must fail (a ray with a leaf visit or a node fetch lives longer),
# which shows the monitor can catch a ray that overstays its bound.
mutant short_bound "(probe) responseBound 16 instead of 80: a ray that lives longer must be caught" \
  "s/ageReg_0 < 7'h50/ageReg_0 < 7'h10/" "ageReg_0 < 7'h50" bounded_response_1
exit $status
