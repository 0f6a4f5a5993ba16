#!/usr/bin/env bash
# make regress: one scene through the RTL, ray by ray against the golden model
# and against Embree. Variables (all optional but SCENE):
#   SCENE=scenes/x/x.xml | a compiled package directory
#   RAYS=primary|shadow|ao|random|file.txt   SPP=1   WIDTH= HEIGHT=   SEED=1
#   OUT=build/regress/<scene>   FLOAT=e8m23   TRIANGLE=watertight|moller
#   ROUNDING=rne|conservative   MEM_LATENCY=100 (or 50-300)   IDS=64   STACK=
#   CACHE=0 (KiB)   MAX_RAYS=   WAVES=0   STRICT=0   SIZE=1 (hardware sized to the scene)
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
  "$bridge" "${args[@]}"
fi
start=$(date +%s)
opts="--package $pkg --out $OUT --float ${FLOAT:-e8m23} --triangle ${TRIANGLE:-watertight}"
opts+=" --rounding ${ROUNDING:-rne} --mem-latency ${MEM_LATENCY:-100} --ids ${IDS:-64} --cache ${CACHE:-0}"
opts+=" --waves ${WAVES:-0} --strict ${STRICT:-0} --seed ${SEED:-1} --bridge $bridge"
# Empty values would vanish in sbt's argument splitting: pass only what is set.
[ -n "${STACK:-}" ] && opts+=" --stack $STACK"
[ -n "${MAX_RAYS:-}" ] && opts+=" --rays $MAX_RAYS"
[ -n "${SIZE:-}" ] && opts+=" --size $SIZE"
./sbt "Test/runMain rtaccel.regress.Regress $opts"
echo "regress: $OUT/report.md ($(( $(date +%s) - start )) s)"
