# plcsynth: the two commands of the README are `make serve` and `make test`.
# Every install step is idempotent and works as root on a fresh machine.

CARGO ?= cargo

.PHONY: test test-native checkers

## Run every test: native unit, integration and property tests, against the independent checkers.
test: test-native

## Independent checkers (libFAUDES, blark, awlsim in .venv; xmllint from Debian).
checkers:
	bash scripts/python-checkers.sh

test-native: checkers
	$(CARGO) test --all-targets --release
	$(CARGO) test --doc --release
