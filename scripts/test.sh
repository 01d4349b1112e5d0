#!/usr/bin/env bash
# `make test`: every test, arranged so that a fresh 2-core machine stays busy.
#
# What is installed from the network (Debian packages, PyPI, npm, and wasm-bindgen-cli from
# crates.io) runs in the background while the lints and the native tests compile; the native
# tests run with cargo-nextest when it is installed (a process per test, two at a time), else
# with `cargo test`. Nothing is cached between runs: each step installs
# only what is missing, as `make checkers`, `make web-setup` and `make browser-setup` do.
#
# The WebAssembly builds (lint, the boundary's tests, the playground) run in the background
# during the native tests, in target/wasm-jobs.
#
# Environment: CARGO (default cargo), TEST_PROFILE (default test-opt).
set -euo pipefail
cd "$(dirname "$0")/.."
cargo=${CARGO:-cargo}
profile=${TEST_PROFILE:-test-opt}
mkdir -p target
say() { echo "test: $*" >&2; }
stamp() { date +%s; }
started=$(stamp)
phase() { say "$1 ($(($(stamp) - started)) s)"; }

# 1. Installs in the background (network-bound; apt-get and pip one after the other): the
#    checkers first, which the native tests need; then the playground's tools, which only the
#    WebAssembly builds and the browser tests need, so the native tests do not wait for them.
setup_log=target/setup.log
checkers_ready=target/checkers.ready
web_ready=target/web.ready
setup_broke=target/setup.failed
rm -f "$checkers_ready" "$web_ready" "$setup_broke"
# In a process group of its own, so that stopping the tests stops the installs too.
setsid bash -c "{ bash scripts/python-checkers.sh && touch $checkers_ready && bash scripts/setup-web.sh --browser && touch $web_ready; } || { touch $setup_broke; exit 1; }" \
    >"$setup_log" 2>&1 </dev/null &
setup_pid=$!
setup_failed() {
    say "installing the checkers or the playground's tools failed:"
    cat "$setup_log" >&2
    exit 1
}
wait_checkers() {
    while [[ ! -e $checkers_ready ]]; do
        [[ ! -e $setup_broke ]] || setup_failed
        sleep 1
    done
    phase "checkers ready (installed at $(($(stat -c %Y "$checkers_ready") - started)) s)"
}
wait_setup() {
    wait "$setup_pid" || setup_failed
    phase "wasm-bindgen, npm packages and Chromium ready (installed at $(($(stat -c %Y "$web_ready") - started)) s)"
}
trap 'kill -- -"$setup_pid" 2>/dev/null || true' EXIT

# 2. Formatting, then clippy's lints (warnings as errors) while the tests compile: clippy-driver
#    is the compiler of this package's own crates (RUSTC_WORKSPACE_WRAPPER and CLIPPY_ARGS, as
#    `cargo clippy` sets them), so the dependencies are compiled once instead of checked for
#    clippy and then compiled again (about 150 CPU-s). The lints see every target `cargo clippy
#    --all-targets` sees: the library, its unit tests, the CLI, the integration tests and the
#    benchmarks here, and the wasm boundary (src/wasm) in the wasm32 build of step 4.
#    CLIPPY_ARGS is cargo-clippy's private protocol with clippy-driver: a canary that has two
#    lints must compile without it and fail with it, else (or without clippy-driver) `cargo
#    clippy` runs first, as `make lint` does.
phase "lint"
$cargo fmt --check
clippy_driver=$(rustup which clippy-driver 2>/dev/null || command -v clippy-driver || true)
clippy_args="-D__CLIPPY_HACKERY__warnings__CLIPPY_HACKERY__"
canary=target/clippy-canary
mkdir -p "$canary"
printf 'fn main() {\n    let v = vec![1];\n    if v.len() == 0 {\n        println!("empty");\n    }\n}\n' >"$canary/canary.rs"
lint_canary() { "$clippy_driver" --edition 2021 --emit=metadata --out-dir "$canary" "$canary/canary.rs" >/dev/null 2>&1; }
if [[ -n $clippy_driver ]] && lint_canary && ! CLIPPY_ARGS=$clippy_args lint_canary; then
    export RUSTC_WORKSPACE_WRAPPER=$clippy_driver
    export CLIPPY_ARGS=$clippy_args
else
    say "clippy-driver missing or not denying lints through CLIPPY_ARGS: linting with cargo clippy first"
    $cargo clippy --all-targets --profile "$profile" --features wasm-lint -- -D warnings
fi

# 3. Native tests: build (and lint) while the installs finish, then run against the checkers.
#    The benchmarks are built, not run (`cargo bench` and `plcsynth bench` run them): 13 CPU-s.
targets="--lib --bins --tests"
phase "build (and lint) the native tests and the benchmarks"
nextest=0
if $cargo nextest --version >/dev/null 2>&1; then nextest=1; fi
if [[ $nextest -eq 1 ]]; then
    $cargo nextest run --cargo-profile "$profile" $targets --no-run
else
    $cargo test $targets --profile "$profile" --no-run
fi
$cargo build --benches --profile "$profile"
wait_checkers

# 4. The WebAssembly builds (the boundary's tests, the playground) and the boundary's tests in
#    Node (a single-threaded minute: it fits beside the native tests better than after them) in
#    the background, in a target directory of their own so that they never wait for the native
#    run's cargo, once the playground's tools are installed (the installs fail: they stop at once).
wasm_log=target/wasm-build.log
wasm_target_dir=$PWD/target/wasm-jobs
# The boundary's tests build without debug info: a sixth of the module (13 MB instead of 86) for
# wasm-bindgen-test-runner to rewrite, and 20 CPU-s less to build; the name section stays, so a
# failing test's backtrace still names its functions. That build is where clippy lints the wasm
# boundary (step 2's wrapper); the playground's release build needs no second lint. Nor does it
# keep incremental state, which a one-shot build only writes (6 of its 36 CPU-s for this crate).
setsid env CARGO_TARGET_DIR="$wasm_target_dir" CARGO_PROFILE_DEV_DEBUG=false CARGO_PROFILE_DEV_INCREMENTAL=false bash -c "
    set -e
    while [[ ! -e $web_ready ]]; do [[ ! -e $setup_broke ]] || exit 1; sleep 1; done
    $cargo test --target wasm32-unknown-unknown --no-default-features --test wasm_api --no-run
    env -u RUSTC_WORKSPACE_WRAPPER -u CLIPPY_ARGS bash scripts/build-web.sh
    $cargo test --target wasm32-unknown-unknown --no-default-features --test wasm_api
" >"$wasm_log" 2>&1 </dev/null &
wasm_pid=$!
trap 'kill -- -"$setup_pid" 2>/dev/null || true; kill -- -"$wasm_pid" 2>/dev/null || true' EXIT

phase "run the native tests"
if [[ $nextest -eq 1 ]]; then
    $cargo nextest run --cargo-profile "$profile" $targets --no-fail-fast \
        --status-level fail --final-status-level slow
else
    $cargo test $targets --profile "$profile"
fi
$cargo test --doc --profile "$profile"

# 5. The wasm boundary's results, then the page in headless Chromium, on what step 4 built.
wait_setup
if ! wait "$wasm_pid"; then
    say "the WebAssembly builds or the wasm boundary's tests failed:"
    cat "$wasm_log" >&2
    exit 1
fi
phase "wasm tests (run beside the native tests): $(grep -E '^test result' "$wasm_log" | tail -1)"
phase "browser tests"
node --test --test-concurrency=2 tests/browser/
phase "all tests passed"
