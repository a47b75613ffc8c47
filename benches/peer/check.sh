#!/usr/bin/env bash
# Builds the CasADi peer at N = 8 in a temporary directory and checks its
# equilibrium against `fpc finger` (check.py). CI runs it; so can anyone.
#
#   benches/peer/check.sh FPC_BIN [VENV]
#
# VENV: a Python venv to install casadi and numpy into (created if it does
# not exist); without it, a throwaway venv in $TMPDIR.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
if [ $# -lt 1 ] || [ $# -gt 2 ]; then
  echo "usage: $0 FPC_BIN [VENV]" >&2
  exit 2
fi
fpc="$1"
venv="${2:-}"
if [ -z "$venv" ]; then
  tmp="$(mktemp -d)"
  trap 'rm -rf "$tmp"' EXIT
  venv="$tmp/venv"
fi
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check casadi numpy
"$venv/bin/python" "$here/check.py" --fpc "$fpc"
