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
# (setundef -expose), which is what `anyseq` means. If <dir>/stub_<case>.sv
# exists, its modules replace the design's modules of the same name (the
# system proofs read FormalCoreStub over RtAccel this way).
formal_aig() {
  local dir=$1 name=$2 sv=$3 out=$4 prop=${5:-}
  local keep="" over=""
  [ -f "$dir/stub_$name.sv" ] && over="read_verilog -formal -sv -overwrite $dir/stub_$name.sv;"
  [ -n "$prop" ] && keep="chformal -assert -remove t:\$assert c:*$prop %d;"
  # Written whole and renamed into place: two checks may run side by side (make test's formal-test), and a
  # reader must never see the other's half-written copy (the content is the same).
  sed 's/(\* anyseq \*) //' "$dir/FormalAnySeq.v" > "$dir/FormalAnySeq_aig.v.$$" && mv -f "$dir/FormalAnySeq_aig.v.$$" "$dir/FormalAnySeq_aig.v"
  yosys -q -l "${out%.aig}.yosys.log" -p "read_verilog -formal -sv $dir/FormalAnySeq_aig.v $sv $dir/wrap_$name.sv; $over
      prep -flatten -top formal_$name; $keep memory_map; opt -fast; async2sync;
      setundef -undriven -expose; opt_clean; techmap; opt -fast; dffunmap; abc -g AND -fast; opt_clean; dffunmap;
      write_aiger -zinit -map ${out%.aig}.map $out" >/dev/null 2>&1
}

# bmc <aig> <depth> <log> [seconds]: prints "pass" if no assertion fails in steps
# 1..depth (step 1 is reset), else the step of the shortest failure. With a time
# limit (seconds > 0), a check the limit stops prints "limit:<n>": no assertion
# fails in steps 1..n, and steps past n were not checked.
formal_bmc() {
  local limit=""; [ "${4:-0}" -gt 0 ] && limit=" -T $4"
  yosys-abc -c "read_aiger $1; fold; strash; bmc3 -F $2$limit -v" > "$3" 2>&1 || true
  # bmc3 ends every run with "Resource limit reached (...)"; only "(timeout" means the time limit cut it short.
  if grep -q "No output asserted in" "$3" && grep -q "Resource limit reached (timeout" "$3"; then
    echo "limit:$(grep -oE "No output asserted in [0-9]+" "$3" | grep -oE "[0-9]+$" | tail -1)"
  elif grep -q "No output asserted in" "$3"; then echo pass
  else
    local f; f=$(grep -oE "was asserted in frame [0-9]+" "$3" | grep -oE "[0-9]+$" | head -1)
    [ -n "$f" ] && echo $((f + 1)) || echo error
  fi
}

# mutant <name> <what> <sed expression> <text the edit must find> <properties...>:
# a sed edit of a scratch copy of $dir/formal_$case_.sv, checked to depth
# $cdepth with each expected property alone (the others removed); appends to
# $log and sets status=1 if a property does not catch it (globals: dir, log,
# status, case_, cdepth).
mutant() { # name, what it breaks, sed expression, a text the edit must find, expected properties... (case: $case_)
  local name=$1 what=$2 expr=$3 must=$4; shift 4
  local sv=$dir/mutant_$name.sv orig=$dir/formal_$case_.sv
  grep -qF -- "$must" "$orig" || { echo "mutant $name: '$must' not in formal_$case_.sv (update the mutant)" | tee -a "$log"; status=1; return; }
  sed -e "$expr" "$orig" > "$sv"
  if cmp -s "$sv" "$orig"; then echo "mutant $name: sed changed nothing" | tee -a "$log"; status=1; return; fi
  echo "mutant $name ($case_): $what" | tee -a "$log"
  for prop in "$@"; do
    local start=$(date +%s) step
    formal_aig "$dir" "$case_" "$sv" "$dir/mutant_${name}_$prop.aig" "$prop"
    step=$(formal_bmc "$dir/mutant_${name}_$prop.aig" "$cdepth" "$dir/mutant_${name}_$prop.log")
    if [ "$step" != pass ] && [ "$step" != error ]; then
      echo "  $prop: CAUGHT, shortest counterexample $step steps (step 1 is reset), $(( $(date +%s) - start )) s" | tee -a "$log"
    else
      echo "  $prop: NOT CAUGHT within $cdepth steps ($step)" | tee -a "$log"; status=1
    fi
  done
}

# verdict <abc log>: proved / counterexample at <step> / no verdict (pdr, ind).
verdict() {
  if grep -qiE "Property proved|Networks are equivalent" "$1"; then echo proved
  elif f=$(grep -oE "asserted in frame [0-9]+" "$1" | grep -oE "[0-9]+$" | head -1) && [ -n "$f" ]; then echo "counterexample at step $((f + 1))"
  else echo "no verdict"; fi
}
# engine <aig> <label> <abc commands>: runs an unbounded engine, appends its verdict and time to $log.
engine() {
  local aig=$1 label=$2 cmd=$3 out start v
  out=${aig%.aig}_$label.log; start=$(date +%s)
  yosys-abc -c "read_aiger $aig; fold; strash; $cmd" > "$out" 2>&1 || true
  v=$(verdict "$out")
  echo "  $label ($cmd): $v, $(( $(date +%s) - start )) s" | tee -a "$log"
}
