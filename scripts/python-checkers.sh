#!/usr/bin/env bash
# Creates the git-ignored virtualenv `.venv` holding the independent checkers used by the
# tests (libFAUDES via `pip install faudes`). Idempotent: does nothing when already installed.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ ! -x .venv/bin/python ]; then
  python3 -m venv .venv
fi
if ! .venv/bin/python -c 'import faudes' >/dev/null 2>&1; then
  .venv/bin/pip install --quiet faudes
fi
.venv/bin/python -c 'import faudes; print("libFAUDES", faudes.Version() if hasattr(faudes, "Version") else "ok")'
