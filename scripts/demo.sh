#!/usr/bin/env bash
# make demo: the regression on the default scene (the Cornell box, 64x64
# camera rays, FP32 watertight, conservative boxes, DDR memory model), then
# the picture of what the hardware saw, then the box shaded at 256x256 from
# RTL-traced rays.
set -euo pipefail
# SIM=cpp (default): the regression runs the system top under the C++
# Verilator harness through librtaccel (sw/sim/), ~30k cycles/s here;
# SIM=chiseltest runs it under chiseltest (~2k cycles/s: minutes more).
# CPPSIM_CLANG=0 (default here): the gcc model build, the one make test
# makes. The clang one runs about 10% faster (docs/cppsim.md) but is a second
# model build (and clang's install on a new machine), which a first demo of
# about 25k cycles would pay many times over.
export SCENE=scenes/cornell-box/cornell-box.xml OUT=${OUT:-build/demo} ROUNDING=${ROUNDING:-conservative} SIM=${SIM:-cpp} CPPSIM_CLANG=${CPPSIM_CLANG:-0}
scripts/regress.sh
# The Cornell box shaded (eye light), 256x256, every camera ray traced by the
# RTL (the Verilated system through librtaccel, make render RTL=1), beside
# Embree's image and the difference; checked pixel for pixel against golden.
make -s --no-print-directory render SCENE="$SCENE" INTEGRATOR=normals RTL=1 OUT="$OUT/shaded"
echo
echo "demo: hardware image   $OUT/hits.png"
echo "demo: Embree image     $OUT/reference.png"
echo "demo: differences      $OUT/diff.png"
echo "demo: shaded 256x256 (RTL hits) $OUT/shaded/montage.png"
echo "demo: full report      $OUT/report.md"
echo "demo: 256x256 shaded images: make render SCENE=scenes/cornell-box/cornell-box.xml INTEGRATOR=direct (RTL=1 for RTL hits)"
