#!/usr/bin/env bash
# make demo: the regression on the default scene (the Cornell box, 64x64
# camera rays, FP32 watertight, conservative boxes, DDR memory model), then
# the picture of what the hardware saw.
set -euo pipefail
export SCENE=scenes/cornell-box/cornell-box.xml OUT=${OUT:-build/demo} ROUNDING=${ROUNDING:-conservative}
scripts/regress.sh
echo
echo "demo: hardware image   $OUT/hits.png"
echo "demo: Embree image     $OUT/reference.png"
echo "demo: differences      $OUT/diff.png"
echo "demo: full report      $OUT/report.md"
