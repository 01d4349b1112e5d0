#!/usr/bin/env bash
# Coverage-guided fuzzing (docs/fuzzing.md): installs cargo-fuzz if missing, seeds each
# target's corpus from the project's own inputs and runs the targets one after the other,
# single process, FUZZ_SECONDS each. Usage: scripts/fuzz.sh [TARGET...] (default: all).
# Crashes land in fuzz/artifacts/<target>/; corpora grow in fuzz/corpus/<target>/ (both ignored
# by git).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${FUZZ_SECONDS:-60}"
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(tga sct gen wmod tlsf ltl verdict share)

rust_targets=()
for t in "${targets[@]}"; do [ "$t" = share ] || rust_targets+=("$t"); done
if [ ${#rust_targets[@]} -gt 0 ]; then
  rustup run nightly rustc --version >/dev/null 2>&1 || rustup toolchain install nightly --profile minimal
  command -v cargo-fuzz >/dev/null || cargo install cargo-fuzz
fi

seed() { # seed TARGET FILE... : copies files into the target's corpus (idempotent)
  local dir="fuzz/corpus/$1"
  shift
  mkdir -p "$dir"
  for f in "$@"; do [ -f "$f" ] && cp -n "$f" "$dir/" || true; done
}

for t in "${targets[@]}"; do
  case "$t" in
    tga) seed tga examples/timed/*.tga tests/fixtures/thesis/*.tga tests/fixtures/fuzz/tga/* ;;
    sct) seed sct examples/sct/*.sct tests/fixtures/fuzz/sct/* ;;
    gen) seed gen fuzz/seeds/gen/* tests/fixtures/fuzz/gen/* ;;
    wmod) seed wmod fuzz/seeds/wmod/* tests/fixtures/wmod/*.wmod tests/fixtures/fuzz/wmod/* ;;
    ltl) seed ltl ../shared/ltl/g4ltl/*.g4ltl examples/ltl/*.ltl tests/fixtures/fuzz/ltl/* ;;
    tlsf) seed tlsf ../shared/ltl/tlsf/*/*.tlsf examples/ltl/*.tlsf tests/fixtures/fuzz/tlsf/* ;;
    verdict) mkdir -p fuzz/corpus/verdict ;; # bytes choose a specification: no text seeds
    share) ;;
    *) echo "unknown fuzz target $t (tga, sct, gen, wmod, tlsf, ltl, verdict, share)" >&2; exit 2 ;;
  esac
  echo "== fuzz $t for ${seconds}s"
  if [ "$t" = share ]; then
    node fuzz/share/fuzz.mjs "$seconds" # www/src/share.js in Node: docs/fuzzing.md
  else
    # -a: debug assertions and overflow checks, as in the test-opt profile. -s none: the crate
    # has no unsafe code, and AddressSanitizer would cost most of the speed. Inputs up to 4 KiB
    # (the larger examples are cut); one input may take 10 s (parsers) or 20 s (verdict)
    # before it counts as a hang.
    timeout=10
    [ "$t" = verdict ] && timeout=20
    (cd fuzz && cargo +nightly fuzz run -a -s none "$t" "corpus/$t" -- \
      -max_total_time="$seconds" -max_len=4096 -timeout="$timeout" -rss_limit_mb=4096 -print_final_stats=1)
  fi
done
