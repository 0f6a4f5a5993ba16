#!/usr/bin/env bash
# make render: a shaded image of a Nori scene from the accelerator's hits,
# beside Embree's image of the same rays, their difference and a montage.
#   SCENE=scenes/x/x.xml  INTEGRATOR=normals|ao|direct (default ao)
#   WIDTH=256 HEIGHT=256 SPP=1 (camera samples per pixel)
#   SAMPLES=4 (AO rays, or light samples, per camera hit)  SEED=1
#   RTL=1: hits from the RTL (the Verilated rtaccel_system driven by
#          librtaccel, rtaccel-sim in $RTL_SIMDIR) instead of the golden walk;
#          each hit checked against the golden walk, and the image rendered
#          again from golden hits (OUT/golden/) and compared pixel for pixel
#   OUT=build/render/<scene>-<integrator>
#   WHY=1: pixels differing from Embree's image explained ray by ray (OUT/why.json)
# Stages: camera rays -> hits -> secondary rays (ao, direct) -> hits -> shade.
# The hit source is the only thing RTL=1 changes; shading is a function of
# the hits alone, so equal hits give equal pixels.
set -euo pipefail
: "${SCENE:?make render needs SCENE=scenes/<name>/<name>.xml}"
[ -f "$SCENE" ] || { echo "Error: $SCENE: no such scene file" >&2; exit 2; }
bridge=nori-bridge/target/release/nori-bridge
golden=nori-accel/build/golden-trace
integ=${INTEGRATOR:-ao}
case "$integ" in normals|ao|direct) ;; *) echo "Error: INTEGRATOR=$integ (normals, ao or direct)" >&2; exit 2;; esac
name=$(basename "${SCENE%.xml}")
OUT=${OUT:-build/render/$name-$integ}
W=${WIDTH:-256} H=${HEIGHT:-256} SAMPLES=${SAMPLES:-4} SEED=${SEED:-1}
source_name=golden; [ "${RTL:-0}" = 1 ] && source_name=RTL
sim=${RTL_SIMDIR:-build/cppsim/test-system}/rtaccel-sim
if [ "${RTL:-0}" = 1 ] && [ ! -x "$sim" ]; then
  echo "Error: $sim: no C++ simulator of the system (make render builds it through make cppsim-test)" >&2; exit 2
fi
mkdir -p "$OUT"
start=$(date +%s.%N)

# hits <package> -> prints the hits.csv path of the chosen source
hits() {
  local pkg=$1
  if [ "${RTL:-0}" = 1 ]; then
    # Every ray through the Verilated system (librtaccel's simulation
    # backend: 200 MHz fabric, 12.8 GB/s DDR, 100 ns latency), then each hit
    # against the golden walk (a mismatch stops the render).
    mkdir -p "$pkg/rtl"
    local t0; t0=$(date +%s.%N)
    "$sim" --package "$pkg" --out "$pkg/rtl" >&2
    local wall; wall=$(echo "$(date +%s.%N) - $t0" | bc)
    local cycles; cycles=$(sed -n 's/.*"batchCycles": *\([0-9]*\).*/\1/p' "$pkg/rtl/sim.json" | head -1)
    local cps; cps=$(sed -n 's/.*"cyclesPerSecond": *\([0-9.]*\).*/\1/p' "$pkg/rtl/sim.json" | head -1)
    printf 'render: %s: %s rays through the RTL: %s cycles, %.1f s wall (%.0f simulated cycles/s)\n' "$pkg" \
      "$(($(wc -l <"$pkg/rays.csv") - 1))" "$cycles" "$wall" "$cps" >&2
    "$golden" --rtl-hits "$pkg" "$pkg/rtl/hits.bin" "$pkg/rtl/hits.csv" >&2
    echo "$pkg/rtl/hits.csv"
  else
    "$golden" "$pkg" "$pkg/hits-golden.csv" >&2
    echo "$pkg/hits-golden.csv"
  fi
}

"$bridge" compile "$SCENE" --out "$OUT/camera" --rays primary --width "$W" --height "$H" --spp "${SPP:-1}" --seed "$SEED" --bvh 4 >/dev/null
h1=$(hits "$OUT/camera")
opts=(--integrator "$integ" --samples "$SAMPLES" --seed "$SEED")
sec=()
if [ "$integ" != normals ]; then
  "$bridge" shade-rays --package "$OUT/camera" --hits "$h1" "${opts[@]}" --out "$OUT/secondary.txt"
  if grep -qv '^#' "$OUT/secondary.txt"; then
    "$bridge" compile "$SCENE" --out "$OUT/secondary" --rays "$OUT/secondary.txt" --bvh 4 >/dev/null
    h2=$(hits "$OUT/secondary")
    sec=(--secondary "$OUT/secondary" --secondary-hits "$h2")
  fi
fi
"$bridge" shade --package "$OUT/camera" --hits "$h1" "${opts[@]}" "${sec[@]}" --source "$source_name" --out-dir "$OUT"
echo "render: $OUT/montage.png ($source_name hits, $(printf '%.1f' "$(echo "$(date +%s.%N) - $start" | bc)") s)"
# Pixels that differ from Embree's image: each traced to its rays and their
# compare class (tie, edge, reference_wrong, ...) in OUT/why.json.
if [ "${WHY:-1}" = 1 ] && ! grep -q '"pixels_differing": 0,' "$OUT/shade.json"; then
  scripts/render_why.py "$OUT" "$h1" ${h2:+"$h2"}
fi
if [ "${RTL:-0}" = 1 ]; then
  # The same image from the golden walk's hits, pixel for pixel.
  WHY=0 RTL=0 OUT="$OUT/golden" "$0" >/dev/null
  "$bridge" diff-png "$OUT/accel.png" "$OUT/golden/accel.png" --out "$OUT/rtl-vs-golden.png"
fi
