# plcsynth: the two commands of the README are `make serve` and `make test`.
# Every install step is idempotent and works as root on a fresh machine.

CARGO ?= cargo

.PHONY: test test-native python-checkers

## Run every test: native unit, integration and property tests.
test: test-native

## Independent reference checkers (libFAUDES) in a git-ignored .venv; idempotent.
python-checkers:
	bash scripts/python-checkers.sh

test-native: python-checkers
	$(CARGO) test --all-targets --release
