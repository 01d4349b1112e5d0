# plcsynth: the two commands of the README are `make serve` and `make test`.
# Every install step is idempotent and works as root on a fresh machine.

CARGO ?= cargo

.PHONY: test test-native

## Run every test: native unit, integration and property tests.
test: test-native

test-native:
	$(CARGO) test --all-targets --release
	$(CARGO) test --doc --release
