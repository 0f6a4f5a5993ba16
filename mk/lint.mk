# Code hygiene. One format for each language, applied by `make fmt`:
# scalafmt (.scalafmt.conf, the sbt-scalafmt plugin) and rustfmt (defaults).
# `make test` checks both formats (a few seconds: the Scala check runs in the
# same sbt call as the specs); `make lint` adds clippy, which needs its own
# check build of nori-bridge (about a minute), so it is not in `make test`.
.PHONY: fmt fmt-check lint test-rust-fmt

fmt: setup-sbt ## Format every Scala and Rust source in place
	$(SBT) scalafmtAll Test/scalafmtAll scalafmtSbt
	$(CARGO) fmt --manifest-path $(BRIDGE_MANIFEST)

fmt-check: setup-sbt test-rust-fmt ## Fail on any source that make fmt would change
	$(SBT) scalafmtCheckAll Test/scalafmtCheckAll scalafmtSbtCheck

test-rust-fmt: setup-apt
	$(CARGO) fmt --check --manifest-path $(BRIDGE_MANIFEST)

test-rust: test-rust-fmt

lint: fmt-check ## fmt-check, then clippy on nori-bridge with every warning an error
	$(CARGO) clippy --release --all-targets --manifest-path $(BRIDGE_MANIFEST) -- -D warnings
