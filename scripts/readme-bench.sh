#!/usr/bin/env bash
# Regenerates the measured tables of README.md (`make readme-bench`): runs
# `plcsynth bench ENGINE --markdown --runs $RUNS` with the release build for every ENGINE given
# (default: timed sct ltl) and puts its output between the README's marker comments
#   <!-- bench ENGINE: begin --> ... <!-- bench ENGINE: end -->
# leaving everything else untouched. Safe to run again; README.md is rewritten only once every
# bench has succeeded. RUNS defaults to 3 (`bench timed` with 3 runs takes minutes).
set -euo pipefail
cd "$(dirname "$0")/.."

RUNS="${RUNS:-3}"
CARGO="${CARGO:-cargo}"
engines=("$@")
[ ${#engines[@]} -gt 0 ] || engines=(timed sct ltl)

for engine in "${engines[@]}"; do
    grep -qxF "<!-- bench $engine: begin -->" README.md && grep -qxF "<!-- bench $engine: end -->" README.md || {
        echo "README.md lacks the markers <!-- bench $engine: begin --> / <!-- bench $engine: end -->" >&2
        exit 2
    }
done

"$CARGO" build --release --quiet
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
for engine in "${engines[@]}"; do
    echo "bench $engine --runs $RUNS ..." >&2
    "$CARGO" run --release --quiet -- bench "$engine" --markdown --runs "$RUNS" > "$tmp/$engine.md"
done

python3 - "$tmp" "${engines[@]}" <<'PY'
import pathlib, sys

tmp, engines = pathlib.Path(sys.argv[1]), sys.argv[2:]
readme = pathlib.Path("README.md")
text = readme.read_text()
for engine in engines:
    begin, end = f"<!-- bench {engine}: begin -->\n", f"<!-- bench {engine}: end -->"
    if text.count(begin) != 1 or text.count(end) != 1 or text.index(begin) > text.index(end):
        sys.exit(f"README.md: expected one `{begin.strip()}` before one `{end}`")
    table = (tmp / f"{engine}.md").read_text().strip()
    start = text.index(begin) + len(begin)
    text = text[:start] + "\n" + table + "\n\n" + text[text.index(end):]
readme.write_text(text)
PY
echo "README.md: regenerated ${engines[*]}" >&2
