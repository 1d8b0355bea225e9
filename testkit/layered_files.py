"""Layered files as painting programs write them (issue 30), made by numpy: OpenRaster (.ora,
Krita/GIMP/MyPaint: a zip whose first member is an uncompressed `mimetype`, then
`stack.xml` listing the top layer first, PNG layers under data/, a merged image and a
thumbnail) and Photoshop's *Export Layers to Files* folders (`_0000_Top.png` … , every file
the canvas's size). Arrays are y-up like the core's; values in [0, 1].

    >>> [name for name, *_ in window_scene(64)]
    ['sky', 'hill', 'figure']
"""
import os
import tempfile
import zipfile
from xml.sax.saxutils import quoteattr

import numpy as np

from dynpaint_addon.inputs.imageio import write_png


def window_scene(size=96):
    """A small layered painting, back to front → [(name, what, x, y)]: an opaque sky, a hill
    cut out by its alpha (smaller than the canvas, placed by its corner), and a figure as a
    group of channels (dark, bright, normal) — `what` an RGBA array, or {channel: array}."""
    h = w = int(size)
    y, x = np.mgrid[0:h, 0:w].astype(np.float64)
    u, v = (x + 0.5) / w, (y + 0.5) / h
    sky = np.dstack([0.4 + 0.3 * v, 0.6 + 0.2 * v, np.full_like(u, 0.9), np.ones_like(u)])
    hh, hw = h // 2, w
    hy, hx = np.mgrid[0:hh, 0:hw].astype(np.float64)
    ridge = hh * (0.55 + 0.25 * np.sin((hx + 0.5) / hw * 6.0))
    hill = np.dstack([np.full_like(hx, 0.3), np.full_like(hx, 0.55), np.full_like(hx, 0.25),
                      (hy + 0.5 < ridge).astype(np.float64)])
    r = np.hypot(u - 0.6, v - 0.45) / 0.18
    inside = (r < 1).astype(np.float64)
    nz = np.sqrt(np.clip(1 - r ** 2, 0, 1))
    normal = np.dstack([((u - 0.6) / 0.18 * inside + 1) / 2, ((v - 0.45) / 0.18 * inside + 1) / 2,
                        (nz * inside + (1 - inside) + 1) / 2, inside])
    colour = lambda c, a: np.dstack([np.full_like(u, c[0]), np.full_like(u, c[1]),
                                     np.full_like(u, c[2]), a])
    figure = {"dark": colour((0.25, 0.1, 0.1), inside), "bright": colour((0.95, 0.6, 0.4), inside),
              "normal": normal}
    return [("sky", sky, 0, 0), ("hill", hill, 0, h - hh), ("figure", figure, 0, 0)]


def write_ora(path, size, layers, attributes=None, stack_xml=None):
    """An OpenRaster file of `layers` (back to front, as window_scene gives them) on a
    size × size canvas. attributes: {layer name: {xml attribute: value}} added to its
    element (visibility, composite-op, opacity); stack_xml: written instead of the real one
    (broken files)."""
    attributes = attributes or {}
    with tempfile.TemporaryDirectory() as folder, \
            zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr(zipfile.ZipInfo("mimetype"), "image/openraster", zipfile.ZIP_STORED)
        elements = []

        def png(name, rgba):
            file = os.path.join(folder, name.replace("/", "_") + ".png")
            write_png(file, rgba.astype(np.float32), bits=8)
            z.write(file, f"data/{name}.png")
            return f"data/{name}.png"

        def attrs(name, extra=""):
            more = "".join(f" {k}={quoteattr(str(v))}" for k, v in
                           attributes.get(name, {}).items())
            return f"name={quoteattr(name)}{extra}{more}"
        for name, what, x, y in reversed(layers):          # stack.xml: the top layer first
            if isinstance(what, dict):
                children = "".join(f"<layer {attrs(f'{name}_{c}', ' ' + _place(x, y))} "
                                   f"src=\"{png(f'{name}_{c}', a)}\"/>"
                                   for c, a in what.items())
                elements.append(f"<stack {attrs(name)}>{children}</stack>")
            else:
                elements.append(f"<layer {attrs(name, ' ' + _place(x, y))} "
                                f"src=\"{png(name, what)}\"/>")
        z.writestr("stack.xml", stack_xml if stack_xml is not None else
                   f"<?xml version='1.0' encoding='UTF-8'?>\n<image version=\"0.0.5\" "
                   f"w=\"{size}\" h=\"{size}\"><stack>{''.join(elements)}</stack></image>")
        merged = os.path.join(folder, "mergedimage.png")    # what readers show as a preview
        write_png(merged, np.zeros((size, size, 4), np.float32), bits=8)
        z.write(merged, "mergedimage.png")
    return path


def _place(x, y):
    return f"x=\"{x}\" y=\"{y}\""


def write_photoshop_folder(folder, size, layers):
    """Photoshop's Export Layers to Files of `layers` (back to front): every layer a file the
    canvas's size, numbered from the top (`_0000_figure.png` first); a group's channels go
    to one subfolder (`_0000_figure/figure_dark.png`, …: the reader's convention for a
    layer's channels, Photoshop itself writes groups' layers as files of their own)."""
    os.makedirs(folder, exist_ok=True)
    for number, (name, what, x, y) in enumerate(reversed(layers)):
        stem = f"_{number:04d}_{name}"
        if isinstance(what, dict):
            sub = os.path.join(folder, stem)
            os.makedirs(sub, exist_ok=True)
            for c, a in what.items():
                write_png(os.path.join(sub, f"{name}_{c}.png"), _on_canvas(a, x, y, size),
                          bits=8)
        else:
            write_png(os.path.join(folder, stem + ".png"), _on_canvas(what, x, y, size), bits=8)
    return folder


def _on_canvas(rgba, x, y, size):
    """An RGBA layer (y-up) placed with its top-left corner at (x, y) (y down) on a
    transparent canvas, as Photoshop exports untrimmed layers."""
    out = np.zeros((size, size, 4), np.float32)
    h, w = rgba.shape[:2]
    top = size - y                      # y-up row just above the layer's top edge
    out[top - h:top, x:x + w] = rgba
    return out
