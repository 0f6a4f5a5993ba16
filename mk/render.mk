# Shaded images from the accelerator's hits, and nori-accel (golden walk,
# Nori drop-in). See docs/nori-dropin.md.
.PHONY: render nori-accel nori-accel-bench
BRIDGE_BIN := nori-bridge/target/release/nori-bridge

nori-accel: setup-apt ## Build nori-accel/: the golden walk (bit-exact with the FP32 RTL) and the Nori drop-in
	$(MAKE) -C nori-accel

render: setup nori-accel ## Shaded PNG + Embree image + diff + montage.png [SCENE= INTEGRATOR=normals|ao|direct WIDTH=256 HEIGHT=256 SPP=1 SAMPLES=4 RTL=1 OUT=]
	scripts/render.sh

NORI_ACCEL_BENCH := build/nori-accel-bench
nori-accel-bench: setup nori-accel ## Golden-mode throughput of the Nori drop-in on 2 threads (Cornell 256x256 camera and AO rays, dragon AO) -> build/nori-accel-bench/bench.json
	@mkdir -p $(NORI_ACCEL_BENCH)
	$(BRIDGE_BIN) compile scenes/cornell-box/cornell-box.xml --out $(NORI_ACCEL_BENCH)/cornell-primary --rays primary --width 256 --height 256 --bvh 4 >/dev/null
	$(BRIDGE_BIN) compile scenes/cornell-box/cornell-box.xml --out $(NORI_ACCEL_BENCH)/cornell-ao --rays ao --width 256 --height 256 --bvh 4 >/dev/null
	$(BRIDGE_BIN) compile scenes/dragon/dragon.xml --out $(NORI_ACCEL_BENCH)/dragon-ao --rays ao --width 128 --height 128 --bvh 4 >/dev/null
	@for p in cornell-primary cornell-ao dragon-ao; do nori-accel/build/dropin-check --bench $(NORI_ACCEL_BENCH)/$$p 2; done | tee $(NORI_ACCEL_BENCH)/bench.json
	@echo "nori-accel-bench: $(NORI_ACCEL_BENCH)/bench.json (wall-clock figures depend on the machine's load; mrays_per_cpu_s does not)"
