#!/usr/bin/env bash
# Figures for the notes (not a test): BVH statistics per shipped scene,
# compile time of the 1.07M-triangle dragon pair, Embree reference
# throughput on 2 threads, coherent (primary) and incoherent (ao).
# Usage: bridge-measure.sh NORI_BRIDGE_BINARY OUT_DIR
set -euo pipefail
bin=$1 out=$2
mkdir -p "$out"
report="$out/report.txt"
: > "$report"
say() { echo "$*" | tee -a "$report"; }
field() { python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(eval(sys.argv[2], {}, d))" "$@"; }

say "# nori-bridge measurements, $(date -u +%FT%TZ), $(nproc) cores, load average at start: $(cut -d' ' -f1-3 /proc/loadavg)"
say "## BVH per shipped scene (max leaf size 4)"
say "scene triangles nodes leaves depth largest_leaf sah_cost build_s"
for s in cornell-box icosphere multi-mesh dragon; do
  pkg="$out/$s"
  "$bin" compile "scenes/$s/$s.xml" --out "$pkg" >/dev/null
  say "$s $(field "$pkg/scene.json" 'f"{triangles} {nodes} {leaves} {bvh_depth} {largest_leaf} {sah_cost:.2f}"') $(field "$pkg/package.json" '"%.3f" % timings_seconds["bvh_build"]')"
done

say "## Compile time, scenes/dragon-1m (1,073,934 triangles), 3 runs"
for i in 1 2 3; do
  "$bin" compile scenes/dragon-1m/dragon-1m.xml --out "$out/dragon-1m" --rays random --count 1000 >/dev/null
  say "run $i: $(field "$out/dragon-1m/package.json" '" ".join(f"{k} {v:.3f}" for k, v in timings_seconds.items())') s"
done

say "## Embree reference throughput (2 threads)"
"$bin" compile scenes/dragon/dragon.xml --out "$out/coherent" --width 512 --height 512 >/dev/null
"$bin" compile scenes/dragon/dragon.xml --out "$out/incoherent" --width 256 --height 256 --rays ao --spp 4 >/dev/null
"$bin" compile scenes/dragon-1m/dragon-1m.xml --out "$out/coherent-1m" --width 512 --height 512 >/dev/null
"$bin" compile scenes/dragon-1m/dragon-1m.xml --out "$out/incoherent-1m" --width 256 --height 256 --rays ao --spp 4 >/dev/null
for p in coherent incoherent coherent-1m incoherent-1m; do
  say "$("$bin" bench --package "$out/$p")"
done
say "load average at end: $(cut -d' ' -f1-3 /proc/loadavg)"
