#!/usr/bin/env bash
# Installs what the playground needs, only what is missing (idempotent, works as root, never
# asks a question). Usage: scripts/setup-web.sh [--browser]
#   always:     the wasm32 target, wasm-bindgen-cli at the version of the wasm-bindgen crate in
#               Cargo.lock, npm packages (npm ci; binaryen's wasm-opt comes from npm);
#   --browser:  Debian's Chromium for the browser tests.
set -euo pipefail
cd "$(dirname "$0")/.."
want_browser=0
[[ "${1:-}" == "--browser" ]] && want_browser=1

say() { echo "setup-web: $*" >&2; }

# Debian packages: install only when missing, `apt-get update` at most once per run.
apt_updated=0
apt_install() {
    local pkg=$1
    if ! command -v apt-get >/dev/null; then say "no apt-get; cannot install $pkg"; return 1; fi
    local sudo=""
    if [[ $(id -u) -ne 0 ]]; then
        if command -v sudo >/dev/null; then sudo="sudo -n"; else say "not root; cannot install $pkg"; return 1; fi
    fi
    if [[ $apt_updated -eq 0 ]]; then
        say "apt-get update"
        DEBIAN_FRONTEND=noninteractive $sudo apt-get update -qq </dev/null >&2 || return 1
        apt_updated=1
    fi
    say "apt-get install $pkg"
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "$pkg" </dev/null >&2
}

# 1. The Rust target.
if ! rustup target list --installed | grep -qx wasm32-unknown-unknown; then
    say "rustup target add wasm32-unknown-unknown"
    rustup target add wasm32-unknown-unknown >&2
fi

# 2. wasm-bindgen-cli, exactly the crate's version (the CLI refuses any other).
version=$(awk '/^name = "wasm-bindgen"$/ { getline; gsub(/version = |"/, ""); print; exit }' Cargo.lock)
if [[ -z "$version" ]]; then say "wasm-bindgen not found in Cargo.lock"; exit 1; fi
have=$(wasm-bindgen --version 2>/dev/null | awk '{print $2}' || true)
if [[ "$have" != "$version" ]] || ! command -v wasm-bindgen-test-runner >/dev/null; then
    say "cargo install wasm-bindgen-cli --version $version (a few minutes, once)"
    # Without --locked: the locked build of this version fails on a yanked dependency. An
    # unoptimised build (opt-level 0, no LTO, parallel code generation): the tools only rewrite
    # one module per build (the playground's in 2 s instead of 0.7 s, the wasm tests' 13 MB
    # in about 8 s more), while the 150 crates compile in half the CPU time of opt-level 1
    # (about 190 CPU-s instead of 390 on two cores; the install was a third of a fresh
    # machine's setup). Without the default features: they add TLS (rustls, ring) for a test
    # runner that only talks plain HTTP to a local browser driver or none (Node).
    CARGO_PROFILE_RELEASE_OPT_LEVEL=0 CARGO_PROFILE_RELEASE_LTO=false CARGO_PROFILE_RELEASE_CODEGEN_UNITS=256 \
        CARGO_PROFILE_RELEASE_DEBUG=false \
        cargo install wasm-bindgen-cli --version "$version" --no-default-features --force </dev/null >&2
fi

# 3. npm packages, from package-lock.json.
if [[ ! -f node_modules/.package-lock.json ]] || [[ package-lock.json -nt node_modules/.package-lock.json ]]; then
    say "npm ci"
    npm ci --no-audit --no-fund </dev/null >&2
fi

# 4. Chromium for the browser tests.
if [[ $want_browser -eq 1 ]] && [[ ! -x /usr/bin/chromium ]]; then
    apt_install chromium || { say "cannot install chromium: the browser tests need /usr/bin/chromium"; exit 1; }
fi
exit 0
