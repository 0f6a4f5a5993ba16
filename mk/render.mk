# Shaded images from the accelerator's hits, and nori-accel (golden walk,
# Nori drop-in). See docs/nori-dropin.md.
.PHONY: render nori-accel

nori-accel: setup-apt ## Build nori-accel/: the golden walk (bit-exact with the FP32 RTL) and the Nori drop-in
	$(MAKE) -C nori-accel

render: setup nori-accel ## Shaded PNG + Embree image + diff + montage.png [SCENE= INTEGRATOR=normals|ao|direct WIDTH=256 HEIGHT=256 SPP=1 SAMPLES=4 RTL=1 OUT=]
	scripts/render.sh
