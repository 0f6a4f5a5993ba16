#!/usr/bin/env bash
# make regress: one scene through the RTL, ray by ray against the golden model
# and against Embree. Variables (all optional but SCENE):
#   SCENE=scenes/x/x.xml | a compiled package directory
#   RAYS=primary|shadow|ao|random|file.txt   SPP=1   WIDTH= HEIGHT=   SEED=1
#   OUT=build/regress/<scene>   FLOAT=e8m23   TRIANGLE=watertight|moller
#   BOX_FLOAT= TRI_FLOAT= (one unit's format, e.g. BOX_FLOAT=e8m10 TRI_FLOAT=e8m23; FLOAT= sets both)
#   ROUNDING=conservative|rne   IDS=64   STACK=   MAX_RAYS=   WAVES=0   STRICT=0
#   SIZE=1 (hardware sized to the scene)   BVH=4|2|8|nori|4q|8q (node layout; 4 if unset)
#   BOX_TEST=fp32|grid (grid: a quantized node's child boxes in its grid; BVH=4q or 8q)
#   MEMORY=ddr|onchip   MEM_LATENCY=100 (ns, or 80-300; ddr only)   FABRIC_MHZ=200
#   OUTSTANDING=64   CACHE=0 (KiB; ddr only)
#   SIM=chiseltest|cpp (cpp: the system top under the C++ Verilator harness, sw/sim/, driven by
#   scripts/regress-cpp.sh with no JVM once the RTL is emitted)
set -euo pipefail
: "${SCENE:?make regress needs SCENE=scenes/<name>/<name>.xml (or a package directory)}"
bridge=nori-bridge/target/release/nori-bridge
name=$(basename "${SCENE%.xml}")
OUT=${OUT:-build/regress/$name-${RAYS:-primary}}
mkdir -p "$OUT"
if [ -d "$SCENE" ]; then
  pkg=$SCENE
else
  [ -f "$SCENE" ] || { echo "Error: $SCENE: no such scene file" >&2; exit 2; }
  pkg=$OUT/package
  args=(compile "$SCENE" --out "$pkg" --rays "${RAYS:-primary}" --spp "${SPP:-1}" --seed "${SEED:-1}")
  [ -n "${WIDTH:-}" ] && args+=(--width "$WIDTH")
  [ -n "${HEIGHT:-}" ] && args+=(--height "$HEIGHT")
  # 4-wide nodes by default (the ZC706 configuration); BVH=nori is Nori's binary layout.
  args+=(--bvh "${BVH:-4}")
  "$bridge" "${args[@]}"
fi
start=$(date +%s)
# The hardware and memory options, then the run's own.
hw="--float ${FLOAT:-e8m23} --triangle ${TRIANGLE:-watertight}"
hw+="${BOX_FLOAT:+ --box-float $BOX_FLOAT}${TRI_FLOAT:+ --tri-float $TRI_FLOAT}"
hw+="${BOX_TEST:+ --box-test $BOX_TEST}"
hw+=" --rounding ${ROUNDING:-conservative} --memory ${MEMORY:-ddr} --fabric-mhz ${FABRIC_MHZ:-200}"
hw+=" --outstanding ${OUTSTANDING:-64} --seed ${SEED:-1}"
# Empty values would vanish in sbt's argument splitting: pass only what is set.
[ -n "${IDS:-}" ] && hw+=" --ids $IDS"
[ -n "${STACK:-}" ] && hw+=" --stack $STACK"
[ -n "${SIZE:-}" ] && hw+=" --size $SIZE"
[ -n "${MEM_LATENCY:-}" ] && hw+=" --mem-latency $MEM_LATENCY"
[ -n "${CACHE:-}" ] && hw+=" --cache $CACHE"
run="--waves ${WAVES:-0} --strict ${STRICT:-0} --bridge $bridge"
[ -n "${MAX_RAYS:-}" ] && run+=" --rays $MAX_RAYS"
if [ "${SIM:-chiseltest}" = cpp ]; then
  # The C++ harness: no JVM once the RTL is emitted (scripts/regress-cpp.sh).
  scripts/regress-cpp.sh "$pkg" "$OUT" "$hw" "$run"
else
  ./sbt "runMain rtaccel.regress.Regress --package $pkg --out $OUT $hw $run --sim ${SIM:-chiseltest}"
fi
echo "regress: $OUT/report.md ($(( $(date +%s) - start )) s)"
