#!/bin/sh
# Build the extension zip with Blender's own tool (no Blender binary needed): dist/ by default.
set -e
cd "$(dirname "$0")/.."
OUT="${1:-dist}"
mkdir -p "$OUT"
TOOL=$(.venv/bin/python -c 'import os, bpy; print(os.path.join(bpy.utils.system_resource("SCRIPTS"), "addons_core", "bl_pkg", "cli", "blender_ext.py"))' 2>/dev/null | tail -n 1)
.venv/bin/python "$TOOL" build --source-dir . --output-dir "$OUT"
