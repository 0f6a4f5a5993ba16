# Shared by scripts/formal.sh and scripts/formal-mutants.sh (source it).
# The model checker is ABC's bmc3, run by yosys-abc (shipped with Yosys, no
# solver package needed): Yosys reads the design with its assertions and
# assumptions and writes an AIGER model (assertions become bad-state outputs,
# assumptions invariant constraints, free values primary inputs); bmc3 then
# unrolls it. docs/formal.md has the measurements behind the choice.

# wrap <dir> <case>: a top that holds reset in the first cycle only.
formal_wrap() {
  cat > "$1/wrap_$2.sv" <<WRAP
module formal_$2(input clock);
  reg init = 1'b1;  // reset in the first cycle only
  always @(posedge clock) init <= 1'b0;
  FormalTop_$2 top(.clock(clock), .reset(init));
endmodule
WRAP
}

# aig <dir> <case> <sv> <out.aig> [property]: the AIGER model of <sv> (wrapped
# by wrap_<case>.sv); with [property], every other assertion is removed first.
# FormalAnySeq's free wires are undriven here and become primary inputs
# (setundef -expose), which is what `anyseq` means.
formal_aig() {
  local dir=$1 name=$2 sv=$3 out=$4 prop=${5:-}
  local keep=""
  [ -n "$prop" ] && keep="chformal -assert -remove t:\$assert c:*$prop %d;"
  sed 's/(\* anyseq \*) //' "$dir/FormalAnySeq.v" > "$dir/FormalAnySeq_aig.v"
  yosys -q -l "${out%.aig}.yosys.log" -p "read_verilog -formal -sv $dir/FormalAnySeq_aig.v $sv $dir/wrap_$name.sv;
      prep -flatten -top formal_$name; $keep memory_map; opt -fast; async2sync;
      setundef -undriven -expose; opt_clean; techmap; opt -fast; dffunmap; abc -g AND -fast; opt_clean; dffunmap;
      write_aiger -zinit $out" >/dev/null 2>&1
}

# bmc <aig> <depth> <log>: prints "pass" if no assertion fails in steps
# 1..depth (step 1 is reset), else the step of the shortest failure.
formal_bmc() {
  yosys-abc -c "read_aiger $1; fold; strash; bmc3 -F $2 -v" > "$3" 2>&1 || true
  if grep -q "No output asserted in" "$3"; then echo pass
  else
    local f; f=$(grep -oE "was asserted in frame [0-9]+" "$3" | grep -oE "[0-9]+$" | head -1)
    [ -n "$f" ] && echo $((f + 1)) || echo error
  fi
}
