#!/bin/bash
# On the lent GPU machine (scripts/gpu/README.md), in the repository's copy there: the parts
# gathered in /opt/parts unpacked, then the EEVEE tests, the Grease Pencil cost benchmark and
# the turntable in both engines, the results under $OUT (docs/on-a-gpu.md).
REPO=$(pwd)
log() { echo "== $(date +%T) $*"; }
log start; nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
cp .gpu/part* .gpu/SUMS /opt/parts/ 2>/dev/null
for f in /opt/gl/*.deb; do dpkg -x "$f" /; done; ldconfig
(cd /opt/parts && sha256sum -c --quiet SUMS) || exit 3
mkdir -p /opt/dp && cat /opt/parts/part* | zstd -dq | tar -x -C /opt/dp || exit 4
mkdir -p /opt/dp/lib/python3.11/site-packages     # (a command the tests start finds them too)
echo /opt/dp > /opt/dp/lib/python3.11/site-packages/dp.pth
export PYTHONHOME=/opt/dp PYTHONPATH=/opt/dp:$REPO LD_LIBRARY_PATH=/opt/dp/lib:${LD_LIBRARY_PATH:-}
export DYNPAINT_SKIP_BROWSER=1 PYTHONUNBUFFERED=1
export __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
PY=/opt/dp/bin/python3.11
log tests
timeout 300 $PY -m pytest -p xdist.plugin -p no:cacheprovider -q -n 8 \
    --ignore=tests/blender/test_farm.py tests -k "eevee or blend_files_drawing_lit or drafted" \
    2>&1 | tail -15
log benchmark
timeout 180 $PY benchmarks/grease_pencil_cost.py --size 1024 --runs 1 --out "$OUT/gp.md" \
    2>&1 | grep "^|"
for e in eevee cycles; do
    log "turntable $e"
    { time timeout 60 $PY -m dynpaint_addon turntable portrait --engine $e \
        --out /tmp/tt_$e.mp4; } 2>&1 | tail -4
done
log end
