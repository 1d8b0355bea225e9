#!/bin/bash
# Pack what the GPU checks need for a lent GPU machine (docs/on-a-gpu.md, scripts/gpu/README.md):
# CPython 3.11 and the venv's bpy, numpy, OpenEXR and pytest, in parts that fit one call's
# 64 MiB beside the repository (.gpu/part*, SUMS), and the system libraries Blender's EGL
# drawing needs as Debian packages (.gl/*.deb). Both folders are ignored by git.
set -euo pipefail
cd "$(dirname "$0")/../.."
SP=.venv/lib/python3.11/site-packages
PY=$(sed -n 's/^home = \(.*\)\/bin$/\1/p' .venv/pyvenv.cfg)      # the venv's CPython
REPO_MB=$(( $(git ls-files -z | xargs -0 du -cb | tail -1 | cut -f1) / 1000000 ))
PART=$(( (64 * 1048576 / 1000000 - REPO_MB - 5) * 1000000 ))      # a call: 64 MiB in all
rm -rf .gpu && mkdir -p .gpu .gl
# (Blender's USD Python, Cycles' GPU kernels and the denoiser's GPU devices: not drawn here)
tar -cf - --exclude=__pycache__ \
    --exclude=bpy/5.0/python/lib/python3.11/site-packages/pxr \
    --exclude=bpy/5.0/scripts/addons_core/cycles/lib \
    --exclude='bpy/lib/libOpenImageDenoise_device_cuda*' \
    --exclude='bpy/lib/libOpenImageDenoise_device_hip*' \
    --exclude='bpy/lib/libOpenImageDenoise_device_sycl*' \
    --exclude=lib/python3.11/test --exclude=lib/python3.11/site-packages \
    --exclude='lib/python3.11/config-*' --exclude=lib/python3.11/idlelib \
    --exclude=lib/python3.11/tkinter --exclude=lib/python3.11/ensurepip \
    --exclude=lib/python3.11/turtledemo \
    -C "$SP" bpy numpy numpy.libs OpenEXR.cpython-311-x86_64-linux-gnu.so Imath.py _pytest \
    pytest pluggy iniconfig packaging xdist execnet py.py pygments \
    -C "$PY" bin/python3.11 lib/libpython3.11.so.1.0 lib/python3.11 |
    zstd -12 -T0 -q -o .gpu/payload.tar.zst
(cd .gpu && split -b "$PART" -d payload.tar.zst part && rm payload.tar.zst && sha256sum part* > SUMS)
o='-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 -oDir::State::Lists=/tmp/amd64'
mkdir -p /tmp/amd64/partial && apt-get $o update -qq
(cd .gl && apt-get $o download -qq libegl1 libglvnd0 libopengl0 libgl1 libglx0 libgles2 \
    libx11-6 libx11-data libxcb1 libxau6 libxdmcp6 libbsd0 libmd0 libice6 libsm6 libxext6 \
    libxfixes3 libxi6 libxrender1 libxt6 libxkbcommon0 libvulkan1 zstd libzstd1 libuuid1)
ls -la .gpu; du -sh .gl
