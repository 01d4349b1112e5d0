# plcsynth: the two commands of the README are `make serve` and `make test`.
# Every install step is idempotent and works as root on a fresh machine.

CARGO ?= cargo
PORT ?= 8080

.PHONY: test test-native test-wasm test-browser serve web web-setup browser-setup checkers fuzz

## Run every test: native (against the independent checkers), wasm-bindgen-test (in Node) and
## the browser tests (in Chromium).
test: test-native test-wasm test-browser

## Independent checkers (libFAUDES, blark, awlsim in .venv; xmllint from Debian).
checkers:
	bash scripts/python-checkers.sh

test-native: checkers
	$(CARGO) test --all-targets --release
	$(CARGO) test --doc --release

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
	$(CARGO) test --target wasm32-unknown-unknown --no-default-features --test wasm_api

## The page in headless Chromium (playwright-core); screenshots go to target/screenshots.
test-browser: browser-setup web
	node --test --test-concurrency=1 tests/browser/

## Coverage-guided fuzzing (docs/fuzzing.md; not part of `make test`): runs the targets
## FUZZ_TARGETS (tga sct gen verdict share) one after the other, FUZZ_SECONDS each (default 60),
## with corpora seeded from examples/; installs nightly Rust and cargo-fuzz if missing.
## Crashes land in fuzz/artifacts/<target>/.
FUZZ_SECONDS ?= 60
FUZZ_TARGETS ?= tga sct gen verdict share

fuzz:
	FUZZ_SECONDS=$(FUZZ_SECONDS) bash scripts/fuzz.sh $(FUZZ_TARGETS)
