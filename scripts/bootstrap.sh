#!/usr/bin/env bash
# Create .venv/ at the repo root (Python 3.11, bpy 5.0.1: the oldest Blender
# blender_manifest.toml claims) unless it is already there and current, and with --with-newest
# also .venv-newest/ (Python 3.13, bpy 5.3.0: the newest; README.md, "Tested Blender versions").
# Both install requirements-dev.txt, whose markers pick each Python's bpy and numpy, and this
# project editable (the `dynpaint` command). Also make sure a Chromium is there for the web
# page's tests (installed with apt-get where this runs as root, as CI does). Safe to run every
# time: a stamp file in each environment records what was installed.
set -euo pipefail
cd "$(dirname "$0")/.."
case "${1:-}" in
  --with-newest) with_newest=1 ;;
  "") with_newest=0 ;;
  *) echo "bootstrap: unknown option $1 (use --with-newest, or nothing)" >&2; exit 2 ;;
esac

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
wanted=$(cat requirements-dev.txt pyproject.toml)

find_python() {   # python$1 on PATH, else pyenv's, else nothing
  local cand
  for cand in "python$1" "$(pyenv root 2>/dev/null)"/versions/"$1".*/bin/python"$1"; do
    if command -v "$cand" >/dev/null 2>&1 && "$cand" -c "import sys; sys.exit(sys.version_info[:2] != tuple(map(int, '$1'.split('.'))))" 2>/dev/null; then
      echo "$cand"; return
    fi
  done
}

make_env() {      # make_env DIR PYTHON_VERSION WHY
  local dir=$1 version=$2 why=$3 stamp=$1/.requirements-installed py
  if [ -x "$dir/bin/python" ] && [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$wanted" ]; then
    return
  fi
  py=$(find_python "$version")
  if [ -z "$py" ]; then
    echo "bootstrap: Python $version is required for $dir ($why); none found on PATH or in" \
         "pyenv. Install it (pyenv install $version, uv python install $version, or your" \
         "package manager) and run this again." >&2
    exit 1
  fi
  echo "bootstrap: creating $dir with $($py --version) and installing requirements-dev.txt" >&2
  rm -rf "$dir"
  "$py" -m venv "$dir"
  "$dir/bin/python" -m pip install --quiet --disable-pip-version-check -r requirements-dev.txt
  printf '%s\n' "$wanted" > "$stamp"
}

make_env .venv 3.11 "bpy 5.0.1, the oldest Blender the extension claims"
if [ "$with_newest" = 1 ]; then
  make_env .venv-newest 3.13 "bpy 5.3.0, the newest Blender artists run"
fi
