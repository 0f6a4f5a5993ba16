#!/usr/bin/env bash
# Unbounded proofs (docs/formal.md, "What is proven for all time"), run by
# `make formal-induction` after the emission; not part of make test.
#  1. Units by ABC's pdr (IC3), which either proves an assertion for every
#     reachable state or gives a counterexample: RayIdFreeList alone, every
#     input free (2 and 4 IDs: id_allocated_once, id_count); PrepFetch (2 IDs)
#     and LeafIntersect (2 IDs, fast environment) in RtAccel's
#     environment: their bounded response, once, never refusing a ray.
#  2. The n2 core's safety properties (every assertion but bounded_response,
#     which is bounded by nature), ray_conservation among them so that it
#     strengthens the rest: k-induction (ABC `ind`, with uniqueness
#     constraints) and pdr, each with a time limit; the verdict or "no
#     verdict" goes to formal-induction.log.
# Usage: scripts/formal-induction.sh <dir> [seconds per engine on n2]
set -euo pipefail
dir=$1; secs=${2:-300}
. "$(dirname "$0")/formal-lib.sh"
log=$dir/formal-induction.log
: > "$log"
status=0


# Units, each alone with every input free or in RtAccel's environment
# (FormalUnits): pdr proves every assertion of the harness for all time,
# bounded response included (the age counters make it a safety property).
unit() { # name, what
  formal_wrap "$dir" "$1"
  formal_aig "$dir" "$1" "$dir/formal_$1.sv" "$dir/ind_$1.aig"
  echo "$1: $2: $(tr '\n' ' ' < "$dir/formal_$1.props")" | tee -a "$log"
  engine "$dir/ind_$1.aig" pdr "pdr -T $3"
  tail -1 "$log" | grep -q ": proved," || status=1
}
unit ids2 "RayIdFreeList, 2 IDs, inputs free" 120
unit ids4 "RayIdFreeList, 4 IDs, inputs free" 120
unit fetch2 "PrepFetch, 2 IDs, L = 3, S = 1, bound $(awk '$1=="fetch2"{print $3}' "$dir/cases-deep.txt")" 120
unit leaf2f "LeafIntersect, 2 IDs, L = 1, S = 0, leaves of 1, bound $(awk '$1=="leaf2f"{print $3}' "$dir/cases-deep.txt")" 300

formal_wrap "$dir" n2
yosys -q -l "$dir/ind_n2.yosys.log" -p "read_verilog -formal -sv $dir/FormalAnySeq_aig.v $dir/formal_n2.sv $dir/wrap_n2.sv;
    prep -flatten -top formal_n2; chformal -assert -remove c:*bounded_response*; memory_map; opt -fast; async2sync;
    setundef -undriven -expose; opt_clean; techmap; opt -fast; dffunmap; abc -g AND -fast; opt_clean; dffunmap;
    write_aiger -zinit $dir/ind_n2.aig" >/dev/null 2>&1
echo "n2 core, every assertion but bounded_response ($(grep -v bounded_response "$dir/formal_n2.props" | tr '\n' ' '))" | tee -a "$log"
engine "$dir/ind_n2.aig" ind "orpos; ind -u -F 30 -T $secs"
engine "$dir/ind_n2.aig" pdr "pdr -T $secs"
exit $status
