# plcsynth: the two commands of the README are `make serve` and `make test`.
# Every install step is idempotent and works as root on a fresh machine.

CARGO ?= cargo
PORT ?= 8080

.PHONY: test test-long lint test-native test-wasm test-browser serve web web-setup browser-setup checkers fuzz readme-bench

# The tests build with the `test-opt` profile (Cargo.toml): optimised, no LTO, overflow
# checks on. Release builds (LTO) are for `make serve`, benchmarks and users.
TEST_PROFILE ?= test-opt

## Run every test: formatting and lints, native (against the independent checkers),
## wasm-bindgen-test (in Node) and the browser tests (in Chromium). scripts/test.sh installs
## what is missing in the background while the lints and the native tests compile.
test:
	CARGO=$(CARGO) TEST_PROFILE=$(TEST_PROFILE) bash scripts/test.sh

## The same with the random and property runs ten times bigger, the real-time closed loops
## four times longer, the scan strategies' code 50 runs in awlsim, every generated dialect
## parsed by blark and the page's code pane timed on IL as well as ST (minutes more).
test-long:
	PLCSYNTH_RANDOM_SPECS=4000 PLCSYNTH_PROPTEST_SCALE=10 PLCSYNTH_ALL_DIALECTS=1 PLCSYNTH_REALTIME_RUNS=4 PLCSYNTH_AWLSIM_RUNS=50 PLCSYNTH_FULL_REFERENCE=1 $(MAKE) test

## rustfmt and clippy, warnings as errors; the wasm boundary (src/wasm) is linted on the host
## with the rest (feature wasm-lint), and for wasm32 in test-wasm.
lint:
	$(CARGO) fmt --check
	$(CARGO) clippy --all-targets --profile $(TEST_PROFILE) --features wasm-lint -- -D warnings

## Independent checkers (libFAUDES, blark, awlsim in .venv; xmllint from Debian).
checkers:
	bash scripts/python-checkers.sh

test-native: checkers
	$(CARGO) test --lib --bins --tests --profile $(TEST_PROFILE)
	$(CARGO) test --doc --profile $(TEST_PROFILE)

## Install what the playground needs (wasm32 target, wasm-bindgen-cli, npm packages).
web-setup:
	bash scripts/setup-web.sh

browser-setup:
	bash scripts/setup-web.sh --browser

## Build the static playground into www/pkg and www/dist.
web: web-setup
	bash scripts/build-web.sh

## Serve the playground at http://localhost:$(PORT) (static files only).
serve: web
	@echo "plcsynth playground: http://localhost:$(PORT)/"
	python3 -m http.server --bind 127.0.0.1 --directory www $(PORT)

## The wasm boundary, tested with wasm-bindgen-test in Node.
test-wasm: web-setup
	$(CARGO) clippy --lib --target wasm32-unknown-unknown --no-default-features -- -D warnings
	$(CARGO) test --target wasm32-unknown-unknown --no-default-features --test wasm_api

## The page in headless Chromium (playwright-core); screenshots go to target/screenshots.
test-browser: browser-setup web
	node --test --test-concurrency=2 tests/browser/

## Coverage-guided fuzzing (docs/fuzzing.md; not part of `make test`): runs the targets
## FUZZ_TARGETS (tga sct gen tlsf ltl verdict share) one after the other, FUZZ_SECONDS each (default 60),
## with corpora seeded from examples/; installs nightly Rust and cargo-fuzz if missing.
## Crashes land in fuzz/artifacts/<target>/.
FUZZ_SECONDS ?= 60
FUZZ_TARGETS ?= tga sct gen tlsf ltl verdict share

fuzz:
	FUZZ_SECONDS=$(FUZZ_SECONDS) bash scripts/fuzz.sh $(FUZZ_TARGETS)

## Regenerate README.md's measured tables from `plcsynth bench timed|sct|ltl --markdown`
## (release build, RUNS runs each, default 3; minutes; not part of `make test`).
RUNS ?= 3

readme-bench: checkers
	RUNS=$(RUNS) CARGO=$(CARGO) bash scripts/readme-bench.sh
