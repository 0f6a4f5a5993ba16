#!/usr/bin/env bash
# Breaks the emitted system design (formal_s1.sv, the core replaced by
# FormalCoreStub) on purpose, one way at a time, and checks that the bounded
# model check catches each break with the property meant to catch it; then
# probes (added assertions that must fail) show what the depth reaches
# (docs/formal.md, "System level"). Log: system-mutants.log.
# Usage: scripts/formal-system-mutants.sh <dir> <depth> [probes|mutants|all]
set -euo pipefail
dir=$1; depth=$2; which=${3:-all}
. "$(dirname "$0")/formal-lib.sh"

case_=s1; cdepth=$depth; formal_wrap "$dir" s1
log=$dir/system-mutants.log
: > "$log"
status=0
# Probes: assertions that an event never happens, all in one model; bmc3 -a
# finds each one's shortest counterexample, the first step the event can
# happen (names from Yosys's AIGER map), so the log shows what the depth reaches.
if [ "$which" != mutants ]; then
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
  for what in "reach_start:the host script has ended (START accepted, IRQ_ENABLE = DONE)" "reach_block_read:a ray block has been read from DDR" \
      "reach_hit_written:a hit record is written" "reach_done:DONE (the batch ends)"; do
    name=${what%%:*}
    o=$(awk -v n="${name}_1" '$1 == "output" && index($3, n) {print $2}' "$dir/probes_s1.map" | head -1)
    f=$(grep -oE "Output $o was asserted in frame [0-9]+" "$dir/probes_s1.log" | grep -oE "[0-9]+$" | head -1 || true)
    if [ -n "$o" ] && [ -n "$f" ]; then echo "  $name: step $((f + 1)): ${what#*:}" | tee -a "$log"
    else echo "  $name: not within $depth steps: ${what#*:}" | tee -a "$log"; fi
  done
fi
if [ "$which" != probes ]; then
  mutant hit_twice "HitDma never pops its queue: the same hit record is written again and again" \
    "/^module HitDma(/,/^endmodule/s/\.io_deq_ready     (io_write_ready),/.io_deq_ready     (1'b0),/" \
    ".io_deq_ready     (io_write_ready)," hit_written_once_1
  mutant hit_stride "HitDma writes hit i at HIT_BASE + 64 i (the record size doubled): outside the buffer" \
    "/^module HitDma(/,/^endmodule/s/{_arb_io_out_bits_number\[6:0\], 5'h0}/{_arb_io_out_bits_number[5:0], 6'h0}/" \
    "{_arb_io_out_bits_number[6:0], 5'h0}" hit_in_buffer_1
  mutant ray_renumber "RayDma numbers block 0's rays as block 1's: a hit for a ray not yet read" \
    "/^module RayDma(/,/^endmodule/s/assign io_rays_bits_number = {_GEN_0\[29:0\], subReg};/assign io_rays_bits_number = {_GEN_0[29:0] ^ 30'h1, subReg};/" \
    "assign io_rays_bits_number = {_GEN_0[29:0], subReg};" hit_after_fetch_1
  mutant ray_past_count "RayDma hands out every ray of the last block, also those past RAY_COUNT" \
    "/^module RayDma(/,/^endmodule/s/wire          present = {_GEN_0, subReg} < _GEN_1;/wire          present = 1'b1;/" \
    "wire          present = {_GEN_0, subReg} < _GEN_1;" hit_in_batch_1
  mutant block_same_addr "RayDma reads every block at RAY_BASE: block 0 is read twice" \
    "/^module RayDma(/,/^endmodule/s/addrReg <= addrReg + 12'hC0;/addrReg <= addrReg;/" \
    "addrReg <= addrReg + 12'hC0;" ray_block_read_once_1
  mutant tag_kept "RayDma never marks a block tag busy: a second block goes out with the tag in flight" \
    "/^module RayDma(/,/^endmodule/s/& ~(_taken_T ? 2'h1 << ~(freeReg\[0\]) : 2'h0);/;/" \
    "& ~(_taken_T ? 2'h1 << ~(freeReg[0]) : 2'h0);" ray_block_once_1
  mutant slot_freed_twice "ReadEngine never pops client 0's completion queue: the same slot is picked and freed again" \
    "/^module ReadEngine(/,/^endmodule/s/\.io_deq_ready (_arb_io_in_0_ready \& credit),/.io_deq_ready (1'b0),/" \
    ".io_deq_ready (_arb_io_in_0_ready & credit)," read_slot_freed_once_1
  mutant slot_taken_busy "ReadEngine's free-slot search ignores the busy slots: a request takes a slot in use" \
    "/^module ReadEngine(/,/^endmodule/s/wire \[2:0\]   _GEN_1 = ~busyReg;/wire [2:0]   _GEN_1 = 3'h7;/" \
    "wire [2:0]   _GEN_1 = ~busyReg;" read_slot_taken_once_1
  mutant out_queue_one "ReadEngine's node output queue takes a record only when empty (1 deep, the credit assumes 3)" \
    "/^module Queue3_ReadResp(/,/^endmodule/s/assign io_enq_ready = ~full;/assign io_enq_ready = empty;/;/^module Queue3_ReadResp(/,/^endmodule/s/wire         do_enq = ~full \& io_enq_valid;/wire         do_enq = empty \& io_enq_valid;/" \
    "module Queue3_ReadResp(" no_overflow_read_out_1
  mutant wrong_tag "ReadEngine answers every record with tag 0: the core gets an answer for a read that does not wait" \
    "/^module ReadEngine(/,/^endmodule/s/\.io_enq_bits_tag  (pickTagReg),/.io_enq_bits_tag  (2'h0),/" \
    ".io_enq_bits_tag  (pickTagReg)," core_read_answer_once_1
  mutant done_early "SystemCore finishes one B response early: DONE before the last hit is written" \
    "/^module SystemCore(/,/^endmodule/s/wire          finish = activeReg \& _fabric_io_writesDone - writesBaseReg == countReg;/wire          finish = activeReg \& _fabric_io_writesDone - writesBaseReg + 32'h1 == countReg;/" \
    "wire          finish = activeReg & _fabric_io_writesDone - writesBaseReg == countReg;" batch_conservation_1
fi
exit $status
