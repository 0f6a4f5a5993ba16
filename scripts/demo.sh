#!/usr/bin/env bash
# make demo: the regression on the default scene (the Cornell box, 64x64
# camera rays, FP32 watertight, conservative boxes, DDR memory model), then
# the picture of what the hardware saw, and the same hits shaded.
set -euo pipefail
export SCENE=scenes/cornell-box/cornell-box.xml OUT=${OUT:-build/demo} ROUNDING=${ROUNDING:-conservative}
scripts/regress.sh
# The RTL's own hits, shaded (eye light), beside Embree's and the difference.
nori-bridge/target/release/nori-bridge shade --package "$OUT/package" --hits "$OUT/hits.csv" --integrator normals \
  --source RTL --out-dir "$OUT/shaded"
echo
echo "demo: hardware image   $OUT/hits.png"
echo "demo: Embree image     $OUT/reference.png"
echo "demo: differences      $OUT/diff.png"
echo "demo: shaded (RTL hits) $OUT/shaded/montage.png"
echo "demo: full report      $OUT/report.md"
echo "demo: 256x256 shaded images: make render SCENE=scenes/cornell-box/cornell-box.xml INTEGRATOR=direct (RTL=1 for RTL hits)"
