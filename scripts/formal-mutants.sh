#!/usr/bin/env bash
# Breaks the emitted n2 design on purpose, one way at a time, and checks that
# the bounded model check catches each break with the property meant to catch
# it (docs/formal.md). Each mutant is a sed edit of a scratch copy of
# formal_<case>.sv (n2, or r2 for bounded response); the original is
# untouched. For each expected property the other assertions are removed and
# ABC's bmc3, which unrolls one step at a time, finds the shortest
# counterexample.
# Usage: scripts/formal-mutants.sh <dir> <depth>   (after make formal-emit)
set -euo pipefail
dir=$1; depth=$2
. "$(dirname "$0")/formal-lib.sh"
formal_wrap "$dir" n2
log=$dir/mutants.log
: > "$log"
status=0
case_=n2; cdepth=$depth
mutant fresh_forever "the free list hands out fresh IDs forever, so an ID in flight is issued again" \
  "s/haveFreshReg <= freshReg != 2'h1;/haveFreshReg <= 1'b1;/" "haveFreshReg <= freshReg != 2'h1;" \
  id_allocated_once_1 exactly_once_1
# Only id_freed_once sees this break here: the host refuses a hit fewer times (the environment's bound) than a
# freed ID takes to be handed out again, so the waiting hit leaves before a new ray can take its ID's entries.
mutant free_unfired "an ID is freed while its hit still waits for the host, so the hit could be emitted twice" \
  "s/\(\.io_free_valid *\)(_io_perf_hitsOut_T),/\1(outValidReg),/" "(_io_perf_hitsOut_T)," \
  id_freed_once_1
mutant init_queue_one "InitTraversal's queue holds one ray, not numRayIds: a prepared ray can find it full" \
  "/^module RamQueue_2(/,/^endmodule/{s/assign io_enq_ready = ~storedIs2Reg;/assign io_enq_ready = io_count == 3'h0;/;s/wire \\( *\\)write = ~storedIs2Reg \\& io_enq_valid;/wire \\1write = io_count == 3'h0 \\& io_enq_valid;/}" \
  "module RamQueue_2(" no_overflow_init_1
mutant lose_ray "a ray that ends on the leaf-return lane is never queued for its hit: lost, no ID freed twice, no number twice" \
  "/RamQueue_2_1 doneQs_1 (/,/io_enq_valid/s/(_q_io_enq_valid_T_15)/(1'b0)/" "RamQueue_2_1 doneQs_1 (" \
  traversal_held_count_1
# Not a break: an assertion that no ray ever comes back from a leaf. Its
# shortest counterexample is the first step at which a leaf round trip (box
# test, leaf job, triangle fetches and tests, return to TraversalControl) lies
# inside the checked depth, so the log shows what the depth covers.
mutant reach_leaf_exit "(probe) no ray ever returns from a leaf: fails at the first step a leaf round trip can end" \
  "s/^      if (~reset \& _init_io_broken) begin/      if (~reset \& _leaf_io_out_valid) begin reach_leaf_exit_1: assert(1'b0); end\n&/" \
  "      if (~reset & _init_io_broken) begin" reach_leaf_exit_1
# Not a break either: the core's bounded_response with its derived bound
# (cases.txt) cut to 16. It must fail (a ray with a leaf
# visit or a node fetch lives longer): the monitor catches a ray that
# overstays its bound, though the derived bound itself lies past the depth.
n2bound=$(awk '$1=="n2"{print $3}' "$dir/cases.txt")
bw=1; while [ $(( (1 << bw) )) -lt $(( n2bound + 2 )) ]; do bw=$((bw + 1)); done
hexb=$(printf "%d'h%X" "$bw" "$n2bound")
mutant short_bound "(probe) responseBound 16 instead of $n2bound: a ray that lives longer must be caught" \
  "s/ageReg_0 < $hexb/ageReg_0 < $bw'h10/" "ageReg_0 < $hexb" bounded_response_1

# Per-unit bounded response (FormalUnits), each to its own depth (the bound + 8).
case_=fetch2; cdepth=$(awk '$1=="fetch2"{print $2}' "$dir/cases-deep.txt"); formal_wrap "$dir" fetch2
mutant fetch_lost_answer "PrepFetch drops ray 1's node answers: the ray is lost, which only bounded response sees" \
  "s/io_out_pipe_v <= io_mem_resp_valid;/io_out_pipe_v <= io_mem_resp_valid \& ~io_mem_resp_bits_tag;/" \
  "io_out_pipe_v <= io_mem_resp_valid;" fetch_bounded_response_2
# A probe: with the derived bound (9) cut to 8 the monitor must fail: a ray
# needs 9 cycles here (make formal-deep passes at 9), so the bound is exact.
mutant fetch_tight "(probe) PrepFetch's derived bound 9 cut to 8: a ray needs 9" \
  "s/~(~insideReg_0 | ageReg_0 < 4'h9)/~(~insideReg_0 | ageReg_0 < 4'h8)/" "~(~insideReg_0 | ageReg_0 < 4'h9)" fetch_bounded_response_1
case_=leaf2f; cdepth=$(awk '$1=="leaf2f"{print $2}' "$dir/cases-deep.txt"); formal_wrap "$dir" leaf2f
mutant leaf_stuck_stop "LeafIntersect drops the exit of a ray that stopped issuing (empty leaf, occluded shadow ray): the ray is lost" \
  "s/exitIn_pipe_v <= leaves;/exitIn_pipe_v <= lastAnswer;/" \
  "exitIn_pipe_v <= leaves;" leaf_bounded_response_1
# A probe: LeafIntersect's derived bound 19 cut to 11 must fail: a ray needs
# 12 cycles here (cut to 12, BMC finds none), so the bound has 7 cycles of slack.
mutant leaf_tight "(probe) LeafIntersect's derived bound 19 cut to 11: a ray needs 12" \
  "s/~(~insideReg_0 | ageReg_0 < 5'h13)/~(~insideReg_0 | ageReg_0 < 5'hB)/" "~(~insideReg_0 | ageReg_0 < 5'h13)" leaf_bounded_response_1
exit $status
