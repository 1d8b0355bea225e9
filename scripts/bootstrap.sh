#!/usr/bin/env bash
# Create .venv/ at the repo root (Python 3.11 + requirements-dev.txt) unless it is already
# there and current. Safe to run every time: a stamp file records what was installed.
set -euo pipefail
cd "$(dirname "$0")/.."
stamp=.venv/.requirements-installed
if [ -x .venv/bin/python ] && [ -f "$stamp" ] && cmp -s requirements-dev.txt "$stamp"; then
  exit 0
fi
py=""
for cand in python3.11 python3; do
  if command -v "$cand" >/dev/null 2>&1 && \
     "$cand" -c 'import sys; sys.exit(sys.version_info[:2] != (3, 11))' 2>/dev/null; then
    py=$cand; break
  fi
done
if [ -z "$py" ]; then
  echo "bootstrap: Python 3.11 is required (bpy 5.0.1 is built for it); none found on PATH" >&2
  exit 1
fi
echo "bootstrap: creating .venv with $($py --version) and installing requirements-dev.txt" >&2
rm -rf .venv
"$py" -m venv .venv
.venv/bin/python -m pip install --quiet --disable-pip-version-check -r requirements-dev.txt
cp requirements-dev.txt "$stamp"
