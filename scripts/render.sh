#!/usr/bin/env bash
# make render: a shaded image of a Nori scene from the accelerator's hits,
# beside Embree's image of the same rays, their difference and a montage.
#   SCENE=scenes/x/x.xml  INTEGRATOR=normals|ao|direct (default ao)
#   WIDTH=256 HEIGHT=256 SPP=1 (camera samples per pixel)
#   SAMPLES=4 (AO rays, or light samples, per camera hit)  SEED=1
#   RTL=1: hits from the RTL (make regress on each ray set) instead of the golden walk
#   OUT=build/render/<scene>-<integrator>
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
mkdir -p "$OUT"
start=$(date +%s.%N)

# hits <package> -> prints the hits.csv path of the chosen source
hits() {
  local pkg=$1
  if [ "${RTL:-0}" = 1 ]; then
    # make regress on the package: every ray through the RTL, checked against the golden model.
    SCENE=$pkg OUT=$pkg/rtl scripts/regress.sh >&2
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
