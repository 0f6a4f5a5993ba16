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
    local out=$dir/mutant_${name}_$prop.log start=$(date +%s)
    yosys -l "$out" -q -p "read_verilog -formal -sv $dir/FormalAnySeq.v $sv $dir/wrap_n2.sv;
        prep -flatten -top formal_n2; memory_map; opt -fast; async2sync; dffunmap;
        chformal -assert -remove t:\$assert c:*$prop %d;
        sat -tempinduct -tempinduct-baseonly -maxsteps $depth -prove-asserts -set-assumes -verify -dump_vcd $dir/mutant_${name}_$prop.vcd" \
      >/dev/null 2>&1 || true
    if grep -q "model found for base case: FAIL" "$out"; then
      local step; step=$(grep -oE "Setting up time step [0-9]+" "$out" | tail -1 | grep -oE "[0-9]+$")
      echo "  $prop: CAUGHT, shortest counterexample $step steps (step 1 is reset), $(( $(date +%s) - start )) s, trace mutant_${name}_$prop.vcd" | tee -a "$log"
    else
      echo "  $prop: NOT CAUGHT within $depth steps" | tee -a "$log"; status=1
    fi
  done
}
mutant fresh_forever "the free list hands out fresh IDs forever, so an ID in flight is issued again" \
  "s/wire       haveFresh = freshReg != 2'h2;/wire       haveFresh = 1'b1;/" "wire       haveFresh = freshReg != 2'h2;" \
  id_allocated_once_1 exactly_once_1
mutant free_unfired "an ID is freed while its hit still waits for the host, so the hit is emitted twice" \
  "s/(io_hits_ready & _trav_io_done_valid)/(_trav_io_done_valid)/" "(io_hits_ready & _trav_io_done_valid)" \
  id_freed_once_1
mutant init_queue_one "InitTraversal's queue holds one ray, not numRayIds: a prepared ray can find it full" \
  "/^module Queue2_PreparedEntry/,/^endmodule/{s/assign io_enq_ready = ~full;/assign io_enq_ready = empty;/;s/wire       do_enq = ~full \\& io_enq_valid;/wire       do_enq = empty \\& io_enq_valid;/}" \
  "module Queue2_PreparedEntry" no_overflow_init_1
exit $status
