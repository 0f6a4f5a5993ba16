#!/usr/bin/env bash
# make regress SIM=cpp: one scene package through rtaccel_system under the C++
# Verilator harness (sw/sim/), with no JVM once the RTL is emitted (warm):
#   rtaccel-sim simulates  ->  golden-trace --rtl-hits checks every ray against
#   the C++ golden walk (nori-accel/golden/, TraversalGolden's bit-exact twin)
#   and writes hits.csv  ->  nori-bridge compare judges against Embree  ->
#   nori-bridge render (camera rays)  ->  nori-bridge regress-report writes
#   stats.json, report.json, report.md as the Scala path does.
# Cold (no prepared build of this configuration, or sources newer than it):
# one sbt call, rtaccel.regress.CppSimPrepare, emits the RTL and builds
# rtaccel-sim. A configuration the C++ golden walk does not compute bit for
# bit (not FP32 watertight conservative, stack 64; quantized nodes), SIZE=1
# and WAVES=1 run the Scala path (rtaccel.regress.Regress --sim cpp).
# Called by scripts/regress.sh: regress-cpp.sh <package dir> <out dir> <hardware options> <run options>
set -euo pipefail
pkg=$1 out=$2 hw=$3 run=$4
bridge=nori-bridge/target/release/nori-bridge
scala_path() { ./sbt "runMain rtaccel.regress.Regress --package $pkg --out $out $hw $run --sim cpp"; }
if [ "${SIZE:-0}" = 1 ] || [ "${WAVES:-0}" = 1 ]; then
  echo "regress: SIZE=1 / WAVES=1: the Scala path"; scala_path; exit
fi

# The prepared build of this hardware and memory setting: the image's node layout
# (bytes 44-47 of image.bin), the options, the compiler (CPPSIM_CLANG).
layout=$(od -An -tu4 -j44 -N4 "$pkg/image.bin" | tr -d ' ')
key=$(printf '%s layout=%s clang=%s' "$hw" "$layout" "${CPPSIM_CLANG:-1}" | cksum | cut -d' ' -f1)
prepared=build/cppsim/regress/$key
stamp=$prepared/driver.env
if [ ! -f "$stamp" ] || [ -n "$(find src/main/scala build.sbt sw/sim sw/lib sw/include sw/Makefile -newer "$stamp" -print -quit)" ]; then
  echo "regress: cold: emitting the RTL and building rtaccel-sim (sbt; $prepared)"
  ./sbt "runMain rtaccel.regress.CppSimPrepare --package $pkg --out $out $hw --prepared $prepared"
fi
sim_dir='' sim_options='' golden='' precision_bits=''
# shellcheck source=/dev/null
source "$stamp"
if [ "$golden" != cpp ]; then
  echo "regress: the C++ golden walk is not this configuration's golden model: the Scala path"; scala_path; exit
fi
make -s -C nori-accel build/golden-trace

# MAX_RAYS: the package's first rays, as a package of their own (rays.csv and
# reference.csv list one ray per line after a header), judged and simulated alike.
total=$(( $(wc -l < "$pkg/rays.csv") - 1 ))
rays=${MAX_RAYS:-$total}
(( rays > total )) && rays=$total
run_pkg=$pkg
if (( rays < total )); then
  run_pkg=$out/package-first-$rays
  mkdir -p "$run_pkg"
  cp "$pkg"/{image.bin,scene.json,package.json} "$run_pkg/"
  for f in rays.csv reference.csv; do head -n $(( rays + 1 )) "$pkg/$f" > "$run_pkg/$f"; done
fi
echo "regress: $rays rays; simulator $sim_dir"

t0=$(date +%s.%N)
# shellcheck disable=SC2086 # sim_options is a word list
"$sim_dir/rtaccel-sim" --package "$(realpath "$run_pkg")" --out "$(realpath "$out")" --rays "$rays" $sim_options
t1=$(date +%s.%N)
rc=0
nori-accel/build/golden-trace --rtl-hits "$run_pkg" "$out/hits.bin" "$out/hits.csv" | tee "$out/golden.txt" || rc=$?
mismatches=$(sed -n 's/.*, \([0-9]*\) differ from the golden walk$/\1/p' "$out/golden.txt")
[ -n "$mismatches" ] || { echo "regress: golden-trace failed (exit $rc)" >&2; exit 1; }

"$bridge" compare --package "$run_pkg" --hits "$out/hits.csv" --out "$out/accuracy.json" --precision-bits "$precision_bits"
if (( rays < total )); then
  echo "regress: no images for part of a ray set ($rays of $total rays)"
elif grep -q '"ray_kind": *"primary"' "$pkg/package.json"; then
  "$bridge" render --package "$pkg" --hits "$out/hits.csv" --out-dir "$out"
fi
"$bridge" regress-report --out "$out" --prepared "$prepared/regress.json" --rays "$rays" --golden-mismatches "$mismatches" \
  --wall-seconds "$(awk -v a="$t0" -v b="$t1" 'BEGIN { print b - a }')"
(( mismatches == 0 )) || exit 1
compare_bad=$(grep -o '"mismatches": *[0-9]*' "$out/accuracy.json" | head -1 | grep -o '[0-9]*$' || echo 0)
if [ "${STRICT:-0}" = 1 ] && (( compare_bad > 0 )); then exit 1; fi
