# make fuzz (docs/faults.md, "Fuzzing"): libFuzzer over librtaccel's scene
# loader (an image in memory and as a file) and the scene package's ray reader
# (rays.csv), for FUZZ_SECONDS (default 600), niced, with AddressSanitizer and
# UBSan; seeded from make cppsim-test's Cornell package. A crash, a sanitizer
# report or an undocumented status fails the run and leaves its input in
# build/fuzz/ (crash-*). Not in make test: a bench-like run of fixed length.
# clang and its fuzzer runtime (libclang-rt-dev) come from Debian, installed
# here on first use.
FUZZ_SECONDS ?= 600
FUZZ_DIR := $(BUILD)/fuzz

.PHONY: setup-fuzz fuzz
setup-fuzz: ## Install clang and libFuzzer's runtime from Debian, if missing
	@missing=""; for p in clang libclang-rt-dev; do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q "install ok installed" || missing="$$missing $$p"; done; \
	  if [ -n "$$missing" ]; then \
	    echo "setup-fuzz: installing$$missing"; SUDO=""; [ "$$(id -u)" = 0 ] || SUDO=sudo; \
	    $$SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq $$missing >/dev/null; fi

fuzz: setup setup-fuzz $(CPPSIM_PKG)/image.bin ## Not in make test: libFuzzer over the scene loader and ray reader [FUZZ_SECONDS=600]
	$(MAKE) -s -C sw fuzz BUILD=$(abspath $(FUZZ_DIR))
	rm -rf $(FUZZ_DIR)/seeds && mkdir -p $(FUZZ_DIR)/seeds $(FUZZ_DIR)/corpus
	{ printf '\000'; cat $(CPPSIM_PKG)/image.bin; } > $(FUZZ_DIR)/seeds/image-memory
	{ printf '\001'; cat $(CPPSIM_PKG)/image.bin; } > $(FUZZ_DIR)/seeds/image-file
	{ printf '\002'; head -65 $(CPPSIM_PKG)/rays.csv; } > $(FUZZ_DIR)/seeds/rays-csv
	cd $(FUZZ_DIR) && nice -n 5 ./fuzz/fuzz-loader -max_total_time=$(FUZZ_SECONDS) -max_len=65536 -timeout=10 \
	  -print_final_stats=1 -artifact_prefix=$(abspath $(FUZZ_DIR))/ corpus seeds > fuzz.log 2>&1; \
	  rc=$$?; tail -8 fuzz.log; \
	  echo "fuzz: $(FUZZ_SECONDS) s, exit $$rc ($$(ls crash-* leak-* timeout-* 2>/dev/null | wc -l) crash, leak or timeout inputs); log $(FUZZ_DIR)/fuzz.log"; \
	  exit $$rc
