#!/usr/bin/env bash
# Create .venv/ at the repo root (Python 3.11 + requirements-dev.txt, which installs this
# project editable: the `dynpaint` command) unless it is already there and current, and make sure a Chromium is there for the web page's tests (installed
# with apt-get where this runs as root, as CI does). Safe to run every time: a stamp file
# records what was installed.
set -euo pipefail
cd "$(dirname "$0")/.."

# The exported web page is tested in a real browser: Debian's `chromium`, headless, with its
# software WebGL2. Without root, say what to do instead (README.md, "Tests").
if ! command -v chromium >/dev/null 2>&1 && ! command -v chromium-browser >/dev/null 2>&1 \
    && ! command -v google-chrome >/dev/null 2>&1 && [ -z "${DYNPAINT_CHROMIUM:-}" ]; then
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
    echo "bootstrap: installing chromium (apt-get) for the web page tests" >&2
    DEBIAN_FRONTEND=noninteractive apt-get update -qq >/dev/null
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null
  else
    echo "bootstrap: no Chromium found and not root: install chromium (or Chrome) yourself," \
         "set DYNPAINT_CHROMIUM=/path/to/chrome, or DYNPAINT_SKIP_BROWSER=1 to skip the web" \
         "page tests (README.md, Tests)" >&2
  fi
fi
# what was installed: the requirements and the project's own pyproject.toml (its command)
stamp=.venv/.requirements-installed
wanted=$(cat requirements-dev.txt pyproject.toml)
if [ -x .venv/bin/python ] && [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$wanted" ]; then
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
printf '%s\n' "$wanted" > "$stamp"
