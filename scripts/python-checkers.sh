#!/usr/bin/env bash
# Installs the independent checkers the tests compare against, idempotently:
# - a git-ignored virtualenv `.venv` with libFAUDES (faudes), blark (IEC 61131-3 ST parser),
#   awlsim (an S7 PLC that runs STL/AWL) and gr1py (a GR(1) solver, tests/checkers/ltl_gr1.py);
# - xmllint (Debian libxml2-utils) for the PLCopen TC6 schema;
# - lbt (Debian, an LTL to Büchi translator) for tests/checkers/ltl_mc.py.
set -euo pipefail
cd "$(dirname "$0")/.."
# Both Debian packages in one `apt-get update` and install (the update alone takes seconds).
packages=()
command -v xmllint >/dev/null 2>&1 || packages+=(libxml2-utils)
command -v lbt >/dev/null 2>&1 || packages+=(lbt)
if [ ${#packages[@]} -gt 0 ]; then
  if [ "$(id -u)" = 0 ]; then
    apt-get update -qq && apt-get install -y -qq "${packages[@]}" >/dev/null
  else
    echo "missing: ${packages[*]} (Debian's libxml2-utils gives xmllint, lbt gives lbt); install them as root" >&2
    exit 1
  fi
fi
if [ ! -x .venv/bin/python ]; then
  python3 -m venv .venv
fi
missing=()
.venv/bin/python -c 'import faudes' >/dev/null 2>&1 || missing+=(faudes)
.venv/bin/python -c 'import blark' >/dev/null 2>&1 || missing+=(blark)
.venv/bin/python -c 'import awlsim' >/dev/null 2>&1 || missing+=(awlsim)
[ -x .venv/bin/gr1py ] || missing+=(gr1py)
if [ ${#missing[@]} -gt 0 ]; then
  .venv/bin/pip install --quiet "${missing[@]}"
fi
echo "checkers ready: faudes, blark, awlsim, gr1py, xmllint, lbt"
