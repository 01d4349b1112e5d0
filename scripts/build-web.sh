#!/usr/bin/env bash
# Builds the static playground into www/: the release wasm (size-optimised profile `wasm`,
# LTO, then wasm-opt --merge-similar-functions -Oz when binaryen is installed) as www/pkg, and the JS bundles (esbuild,
# with the examples embedded) as www/dist. Run scripts/setup-web.sh first.
set -euo pipefail
cd "$(dirname "$0")/.."
target_dir=${CARGO_TARGET_DIR:-target}
cargo build --lib --target wasm32-unknown-unknown --profile wasm >&2
raw="$target_dir/wasm32-unknown-unknown/wasm/plcsynth.wasm"
if [[ -f www/pkg/.built-from ]] && [[ "$(cat www/pkg/.built-from)" == "$(stat -c '%Y %s' "$raw") $(sha1sum < scripts/build-web.sh)" ]]; then
    echo "build-web: www/pkg is up to date" >&2
    node www/build.mjs
    exit 0
fi
rm -rf www/pkg.tmp
wasm-bindgen --target web --no-typescript --out-dir www/pkg.tmp "$raw"
wasm=www/pkg.tmp/plcsynth_bg.wasm
# wasm-opt: binaryen from npm (package-lock.json); Debian's binaryen 108 is too old for the
# reference types wasm-bindgen emits (the module then fails at instantiation), so a system
# wasm-opt is used only from version 116 on. Every optimised module is loaded and run once
# (scripts/check-wasm.mjs) before it replaces the unoptimised one.
wasm_opt=""
if [[ -x node_modules/.bin/wasm-opt ]]; then
    wasm_opt=node_modules/.bin/wasm-opt
elif command -v wasm-opt >/dev/null && (( $(wasm-opt --version | grep -o '[0-9]\+' | head -1) >= 116 )); then
    wasm_opt=wasm-opt
fi
if [[ -n "$wasm_opt" ]]; then
    rm -rf www/pkg.opt && cp -r www/pkg.tmp www/pkg.opt
    # --merge-similar-functions first: functions that differ only in constants (generic
    # instances of one layout) become one with a parameter, which -Oz alone does not do.
    if "$wasm_opt" --merge-similar-functions -Oz --enable-bulk-memory --enable-nontrapping-float-to-int --enable-sign-ext \
        --enable-mutable-globals --enable-reference-types --enable-multivalue \
        -o www/pkg.opt/plcsynth_bg.wasm "$wasm" && node scripts/check-wasm.mjs www/pkg.opt; then
        mv www/pkg.opt/plcsynth_bg.wasm "$wasm"
    else
        echo "build-web: wasm-opt failed or broke the module; keeping the unoptimised .wasm" >&2
    fi
    rm -rf www/pkg.opt
else
    echo "build-web: no usable wasm-opt (npm ci installs binaryen); skipping that size step" >&2
fi
echo "$(stat -c '%Y %s' "$raw") $(sha1sum < scripts/build-web.sh)" > www/pkg.tmp/.built-from
rm -rf www/pkg && mv www/pkg.tmp www/pkg
echo "build-web: $(stat -c %s www/pkg/plcsynth_bg.wasm) bytes in www/pkg/plcsynth_bg.wasm" >&2
node www/build.mjs
