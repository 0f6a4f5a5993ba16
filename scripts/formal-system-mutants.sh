#!/usr/bin/env bash
# Breaks the emitted system design (formal_s1.sv, the core replaced by
# FormalCoreStub) on purpose, one way at a time, and checks that the bounded
# model check catches each break with the property meant to catch it; then
# probes (added assertions that must fail) show what the depth reaches
# (docs/formal.md, "System level"). Log: system-mutants.log.
# The system units' mutants (after the system's) break RayDma, HitDma and ReadEngine alone, each checked to
# its unit's depth (system-units.txt).
# Usage: scripts/formal-system-mutants.sh <dir> <depth> [all|probes|mutants|<mutant name>]
set -euo pipefail
dir=$1; depth=$2; which=${3:-all}
. "$(dirname "$0")/formal-lib.sh"

case_=s1; cdepth=$depth; formal_wrap "$dir" s1
log=$dir/system-mutants.log
[ "$which" = all ] || [ "$which" = probes ] || [ "$which" = mutants ] && : > "$log" || true
status=0
want() { [ "$which" = all ] || [ "$which" = mutants ] || [ "$which" = "$1" ]; }
# A mutant runs when `which` selects it (all, mutants, or its name).
maybe_mutant() { want "$1" || return 0; mutant "$@"; }
# Probes: assertions that an event never happens, all in one model; bmc3 -a
# finds each one's shortest counterexample, the first step the event can
# happen (names from Yosys's AIGER map), so the log shows what the depth reaches.
if [ "$which" = all ] || [ "$which" = probes ]; then
  at='      if (~reset \& ~(~isBlock | ~blockReadRegs_0)) begin'
  must='      if (~reset & ~(~isBlock | ~blockReadRegs_0)) begin'
  grep -qF -- "$must" "$dir/formal_s1.sv" || { echo "probes: '$must' not in formal_s1.sv (update the probes)" | tee -a "$log"; exit 1; }
  p() { echo "      if (~reset \\& ($2)) begin $1_1: assert(1'b0); end\\n"; }
  sed -e "s/^$at/$(p reach_start '\&stepReg')$(p reach_block_read isBlock)$(p reach_hit_written _pendingReg_T)$(p reach_done done)&/" \
    "$dir/formal_s1.sv" > "$dir/probes_s1.sv"
  start=$(date +%s)
  formal_aig "$dir" s1 "$dir/probes_s1.sv" "$dir/probes_s1.aig" 'reach_*'
  yosys-abc -c "read_aiger $dir/probes_s1.aig; fold; strash; bmc3 -a -F $depth -v" > "$dir/probes_s1.log" 2>&1 || true
  echo "probes (s1, $(( $(date +%s) - start )) s): the first step (step 1 is reset) at which" | tee -a "$log"
  # Yosys writes the assertions' bad-state outputs in the order of their
  # names (its AIGER map names none of them): reach_block_read, reach_done,
  # reach_hit_written, reach_start are outputs 0..3.
  o=0
  for what in "reach_block_read:a ray block has been read from DDR" "reach_done:DONE (the batch ends)" \
      "reach_hit_written:a hit record is written" "reach_start:the host script has ended (START taken, IRQ_ENABLE = DONE)"; do
    name=${what%%:*}
    f=$(grep -oE "Output $o was asserted in frame [0-9]+" "$dir/probes_s1.log" | grep -oE "[0-9]+$" | head -1 || true)
    if [ -n "$f" ]; then echo "  $name: step $((f + 1)): ${what#*:}" | tee -a "$log"
    else echo "  $name: not within $depth steps: ${what#*:}" | tee -a "$log"; fi
    o=$((o + 1))
  done
fi
if [ "$which" != probes ]; then
  # With a mutant's name as the third argument, only that one runs.
  maybe_mutant done_early "SystemCore finishes one B response early: DONE before the last hit is written" \
    "/^module SystemCore(/,/^endmodule/s/ \& raysDoneReg == countReg;/ \& raysDoneReg + 32'h1 == countReg;/" \
    " & raysDoneReg == countReg;" batch_conservation_1
  maybe_mutant slot_freed_twice "ReadEngine never pops the scene loader's head (client 2): the same slot is granted, picked and freed again" \
    "/^module ReadEngine(/,/^endmodule/s/    \.io_deq_ready (take_2),/    .io_deq_ready (1'b0),/" \
    "    .io_deq_ready (take_2)," read_slot_freed_once_1
  maybe_mutant slot_taken_busy "ReadEngine keeps its drawn slot when a request takes it: the next request takes the same slot, still in use" \
    "/^module ReadEngine(/,/^endmodule/s/    \.io_deq_ready     (meta_MPORT_en),/    .io_deq_ready     (1'b0),/" \
    "    .io_deq_ready     (meta_MPORT_en)," read_slot_taken_once_1
  maybe_mutant tag_kept "RayDma never marks a block tag busy: a second block goes out with the tag in flight" \
    "/^module RayDma(/,/^endmodule/s/& ~(_taken_T ? 2'h1 << ~(freeReg\[0\]) : 2'h0);/;/" \
    "& ~(_taken_T ? 2'h1 << ~(freeReg[0]) : 2'h0);" ray_block_once_1
  maybe_mutant misroute "ReadEngine also delivers every other client's record to the node client: an answer for no waiting read" \
    "/^module ReadEngine(/,/^endmodule/s/    \.io_enq_valid     (_outQs_0_io_enq_valid_T_1),/    .io_enq_valid     (pickValidReg),/" \
    "    .io_enq_valid     (_outQs_0_io_enq_valid_T_1)," core_read_answer_once_1
  maybe_mutant block_same_addr "RayDma reads every block at RAY_BASE: block 0 is read twice" \
    "/^module RayDma(/,/^endmodule/s/addrReg <= addrReg + 12'hC0;/addrReg <= addrReg;/" \
    "addrReg <= addrReg + 12'hC0;" ray_block_read_once_1
  maybe_mutant hit_twice "HitDma never pops its queue: the same hit record is written again and again" \
    "/^module HitDma(/,/^endmodule/s/\.io_deq_ready       (io_write_ready),/.io_deq_ready       (1'b0),/" \
    ".io_deq_ready       (io_write_ready)," hit_written_once_1
  maybe_mutant hit_stride "HitDma writes line p at HIT_BASE + 128 p (the line size doubled): outside the buffer" \
    "/^module HitDma(/,/^endmodule/s/_inQ_io_deq_bits_number\[6:1\], 6'h0}/_inQ_io_deq_bits_number[6:1], 7'h0}/" \
    "_inQ_io_deq_bits_number[6:1], 6'h0}" hit_in_buffer_1
  maybe_mutant rays_early "RayDma hands out rays without waiting for their block: a hit for a ray not read" \
    "/^module RayDma(/,/^endmodule/s/assign io_rays_valid = _q_io_deq_valid \& ~io_stop;/assign io_rays_valid = ~io_stop;/" \
    "assign io_rays_valid = _q_io_deq_valid & ~io_stop;" hit_after_fetch_1
  maybe_mutant ray_skip "RayDma ends a block after its third ray: the fourth ray of a full block is never handed out (lost)" \
    "/^module RayDma(/,/^endmodule/s/wire \( *\)last = subReg == _q_io_deq_bits_lastSub | io_stop/wire \1last = subReg == 2'h2 | subReg == _q_io_deq_bits_lastSub | io_stop/" \
    "last = subReg == _q_io_deq_bits_lastSub | io_stop" system_ray_conservation_1
  maybe_mutant hit_drop "HitDma takes ray 0's hit from the core but never queues its line (alone or paired): the hit is lost" \
    "/^module HitDma(/,/^endmodule/s/= fValidReg | s2ValidReg \& s2InBatchReg \& ~store;/= fValidReg | s2ValidReg \& s2InBatchReg \& ~store \& (|s2HitReg_number);/" \
    "= fValidReg | s2ValidReg & s2InBatchReg & ~store;" system_ray_conservation_1
fi
# The DMA window (case w1: the host sets a free window first): the guard made to pass reads outside it.
# (No hit write happens within w1's depth, so a guard passing writes outside is not caught there:
# docs/formal.md, "The DMA window".)
if [ "$which" != probes ]; then
  case_=w1; cdepth=$(awk '$1=="w1"{print $2}' "$dir/system-cases.txt"); formal_wrap "$dir" w1
  maybe_mutant window_read "WindowGuard forwards every read burst to m_axi, inside the window or not" \
    "/^module WindowGuard(/,/^endmodule/s/\(io_out_ar_valid_0 = ar_validReg\) \& ar_heldReg_ok \& ~fakeRValidReg;/\1 \& ~fakeRValidReg;/" \
    "io_out_ar_valid_0 = ar_validReg & ar_heldReg_ok & ~fakeRValidReg;" window_kept_1
fi
# The system's units alone (make formal-system-units; FormalSystemUnits.scala), each to its own depth
# (system-units.txt): the four properties no system mutant reaches within the system depth are shown able to fail here.
unit_depth() { awk -v u="$1" '$1==u{print $2}' "$dir/system-units.txt"; }
if [ "$which" != probes ]; then
  case_=raydma; cdepth=$(unit_depth raydma); formal_wrap "$dir" raydma
  maybe_mutant ray_past_count "RayDma hands out every ray of the last block, past RAY_COUNT (each block's last ray taken as its fourth)" \
    "/^module RayDma(/,/^endmodule/s/^\( *\)(|(remainingReg\[31:2\])) ? 2'h3 : remainingReg\[1:0\] - 2'h1;/\12'h3;/" \
    "(|(remainingReg[31:2])) ? 2'h3 : remainingReg[1:0] - 2'h1;" raydma_in_batch_1
  maybe_mutant ray_renumber "RayDma numbers each block as the next one (block 0's rays as block 1's)" \
    "/^module RayDma(/,/^endmodule/s/blockOfTag_0 <= issuedReg;/blockOfTag_0 <= issuedReg + 32'h1;/" \
    "blockOfTag_0 <= issuedReg;" raydma_after_block_1 raydma_bounded_response_1
  maybe_mutant ray_skip_unit "RayDma ends a block after its third ray: the fourth ray of a full block is lost" \
    "/^module RayDma(/,/^endmodule/s/wire \( *\)_last_T = subReg == _q_io_deq_bits_lastSub;/wire \1_last_T = subReg == 2'h2 | subReg == _q_io_deq_bits_lastSub;/" \
    "_last_T = subReg == _q_io_deq_bits_lastSub;" raydma_bounded_response_1
  case_=hitdma; cdepth=$(unit_depth hitdma); formal_wrap "$dir" hitdma
  maybe_mutant hit_count_short "HitDma latches RAY_COUNT - 1: the batch's last hit is out of its batch" \
    "/^module HitDma(/,/^endmodule/s/countReg <= io_rayCount;/countReg <= io_rayCount - 32'h1;/" \
    "countReg <= io_rayCount;" hit_in_batch_1
  maybe_mutant hit_drop_unit "HitDma takes ray 0's hit but never queues its line (alone or paired): the hit is lost" \
    "/^module HitDma(/,/^endmodule/s/= fValidReg | s2ValidReg \& s2InBatchReg \& ~store;/= fValidReg | s2ValidReg \& s2InBatchReg \& ~store \& (|s2HitReg_number);/" \
    "= fValidReg | s2ValidReg & s2InBatchReg & ~store;" hitdma_bounded_response_1
  case_=readeng; cdepth=$(unit_depth readeng); formal_wrap "$dir" readeng
  maybe_mutant wrong_tag "ReadEngine answers every record with tag 0" \
    "/^module ReadEngine(/,/^endmodule/s/pickTagReg <= _meta_ext_R1_data\[[0-9]*:[0-9]*\];/pickTagReg <= 2'h0;/" \
    "pickTagReg <= _meta_ext_R1_data[" read_answer_once_1
  maybe_mutant out_queue_one "the node client's output queue (and the loader's, the same module) holds one record, not OutDepth" \
    "/^module Queue3_ReadResp(/,/^endmodule/s/wire \( *\)full = ptr_match \& maybe_full;/wire \1full = ~empty;/" \
    "module Queue3_ReadResp(" no_overflow_read_out_1
  maybe_mutant completion_queue_one "ReadEngine's completion queues hold one slot, not slots" \
    "/^module Queue3_UInt2(/,/^endmodule/s/wire \( *\)full = ptr_match \& maybe_full;/wire \1full = ~empty;/" \
    "module Queue3_UInt2(" no_overflow_read_completion_1
fi
exit $status
