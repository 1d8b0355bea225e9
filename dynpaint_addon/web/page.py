"""A dynamic painting as one self-contained web page (issue 17): the data and the .html file.

The page is the pipeline's fourth backend: the fragment shader is generated from the graph
description (nodegraph/glsl_codegen.py) for the painting's features, its images are the ones
the shader samples (the painting's own and those derived by nodegraph/derived_inputs.py, the
same preparation every backend shares), its uniforms are the parameters and lights. The
viewer (viewer.html, viewer.js, viewer.css beside this file) draws it with WebGL2 and lets the
viewer move the light. Everything is inlined: the file opens offline, with no network and no
external script.

Images are stored losslessly in the precision they have: 8-bit and 16-bit files as their
integer codes, half floats as halves, float data (heights, a normal map's relief) as float32;
each one delta-coded along its rows, split into byte planes and deflated (the browser's
DecompressionStream inflates it), then base64 text.

No bpy: the command line and the add-on both call `page_data` and `write_page`.
"""
import base64
import copy
import dataclasses
import html
import json
import os
import zlib

import numpy as np

from .. import params
from ..core.input_rules import ImageData, pixel_role
from ..core.inputs import about
from ..core.layers import LAYER_QUALITY, Scene
from ..core.pipeline import shape_normals
from ..core.sampling import resample
from ..core.transmittance import EDGE_STEP
from ..inputs.whole_files import write_text_whole
from ..looks import LOOKS, with_look
from ..nodegraph import glsl_codegen
from ..nodegraph.derived_inputs import Source, make_derived, march_bounds, prepare
from ..nodegraph.pipeline_graph import describe, describe_shadow
from ..nodegraph.text_codegen import param_name, read_snippet
from .device_fit import SMALLEST_LEVEL, with_levels

HERE = os.path.dirname(os.path.abspath(__file__))
COLOUR_CHANNELS = {c for c, (_, kind) in params.CHANNELS.items() if kind == "colour"}
TURNTABLE_SECONDS = 8.0          # one turn of the light when the page plays its turntable


def param_uniforms(p):
    """Every numeric parameter's uniform and value (the page's dp.param nodes read them):
    {'p_diffuse_t0': 0.0, 'p_reflection_offset_x': 0.0, …}; 'auto' is 1 (features resolve
    it) and a switch 0 or 1."""
    out = {}
    for prm in params.PARAMS:
        if prm.kind == "enum":
            continue
        value = getattr(getattr(p, prm.section), prm.key)
        for index in prm.components:
            v = value if index is None else value[index]
            out[param_name(prm.path, index)] = 1.0 if v == "auto" else float(v)
    return out


def page_params(p, steps=None):
    """The painting's parameters as the page shows them: the cos-θ term marched in the shader
    (the OSL march's choice of relief, §6), with K = `steps` when given."""
    p = copy.deepcopy(p)
    p.shadows.source = "osl"
    if steps is not None:
        p.shadows.steps = int(steps)
    return p


def shrink(img, max_size):
    """`img` (ImageData) with its longer side at most `max_size` pixels (box-averaged by a
    whole factor, then resampled), or `img` itself."""
    w, h = img.size
    if not max_size or max(w, h) <= max_size:
        return img
    scale = max_size / max(w, h)
    px = img.pixels.astype(np.float32)
    k = int(1 / scale)
    if k > 1:
        px = px[:px.shape[0] // k * k, :px.shape[1] // k * k]
        px = px.reshape(px.shape[0] // k, k, px.shape[1] // k, k, -1).mean(axis=(1, 3))
    out = resample(px, max(1, round(h * scale)), max(1, round(w * scale)))
    return ImageData(out.astype(np.float32), img.bits, img.name)


def encode_pixels(px, kind):
    """(H, W, C) pixels → {'format', 'channels', 'width', 'height', 'data'}: integer codes
    ('u8', 'u16', from values in 0..1) or floats ('f16', 'f32'), row 0 at the bottom, each
    row delta-coded, split into byte planes, deflated, base64."""
    h, w, c = px.shape
    if kind == "u8":
        codes = np.round(np.clip(px, 0, 1) * 255).astype(np.uint8)
    elif kind == "u16":
        codes = np.round(np.clip(px, 0, 1) * 65535).astype("<u2")
    elif kind == "f16":
        codes = px.astype("<f2").view("<u2")
    else:
        codes = px.astype("<f4").view("<u4")
    deltas = codes.copy()
    deltas[:, 1:] -= codes[:, :-1]                       # wraps: undone exactly by a sum
    planes = deltas.reshape(-1).view(np.uint8).reshape(-1, codes.itemsize).T
    data = zlib.compress(np.ascontiguousarray(planes).tobytes(), 6)
    return {"format": kind, "channels": c, "width": w, "height": h,
            "data": base64.b64encode(data).decode("ascii")}


def _kind_of(img):
    """How an input image is stored: its integer codes (8-bit, 16-bit files, and float
    buffers that hold 16-bit codes to float32 rounding, as Blender reads 16-bit data files),
    halves, or floats."""
    if img.bits == 8:
        return "u8"
    px = img.pixels
    if img.bits == 16 or np.abs(np.round(px * 65535) / 65535 - px).max(initial=0) <= 2e-7:
        return "u16"
    return "f16" if _is_half(px) else "f32"


def _is_half(px):
    finite = np.isfinite(px)
    return bool(np.all(finite) and np.abs(px).max(initial=0) < 65504
                and np.array_equal(px.astype(np.float16).astype(px.dtype), px))


def page_textures(features, plan, p, images, cache=None):
    """The images the shader samples → ({channel: encoded texture or {'same_as': channel}},
    warnings). Derived images (plan: derived_inputs.prepare's) replace their sources; colour
    ones (E, B) are halves (≤ 2.4e-4 off in 0..1), data ones (heights, relief) float32.
    cache: {derived key, or the channel of an image used as it is: texture}, shared by the
    calls for one painting's looks."""
    cache = {} if cache is None else cache
    need = {c for c in features.image_channels() if not c.startswith("shadow_")}
    plan = [d for d in plan if d.channel in need]
    todo = [d for d in plan if d.key not in cache]
    made, warnings = make_derived(todo, images.__getitem__, lambda c: pixel_role(c, p))
    by_channel = {d.channel: d for d in plan}
    out = {}
    for channel in sorted(need):
        item = by_channel.get(channel)
        if item is not None and item.same_as:
            out[channel] = {"same_as": item.same_as}
            continue
        key = item.key if item is not None else ("as it is", channel)
        if key in cache:
            out[channel] = cache[key]
            continue
        rgba = made.get(channel) if item is not None else None
        if rgba is not None:
            colour = item.source in COLOUR_CHANNELS
            exact = _is_half(rgba)
            tex = encode_pixels(_fewest_channels(rgba), "f16" if colour or exact else "f32")
            tex["srgb"] = 0
        else:
            img = images[item.source if item is not None else channel]
            tex = encode_pixels(img.pixels, _kind_of(img))
            tex["srgb"] = int(channel in COLOUR_CHANNELS and img.bits < 32)
        out[channel] = cache[key] = tex
    return out, warnings


def _fewest_channels(rgba):
    """RGBA as the fewest channels that hold it: grey (R = G = B) as one, with its alpha as
    two unless that is 1 everywhere (the viewer reads them back as RGBA, the core's way)."""
    grey = np.array_equal(rgba[..., 0], rgba[..., 1]) and \
        np.array_equal(rgba[..., 0], rgba[..., 2])
    if not grey:
        return rgba
    return rgba[..., :1] if np.all(rgba[..., 3] == 1) else rgba[..., [0, 3]]


def _light_entry(light):
    return {"kind": light.kind, "vector": list(light.vector), "colour": list(light.colour),
            "strength": light.strength, "name": light.name or light.kind.title(),
            "size": light.size}


def _march_bounds(images, p, cache):
    """derived_inputs.march_bounds of the shape as the core decodes it (§2, §6); cache:
    {what the decode reads: bounds}, shared by the calls for one painting's looks."""
    key = repr((sorted(vars(p.shape).items()), p.shadows.relief))
    if key not in cache:
        cache[key] = march_bounds(*shape_normals(images["shape"], p, np.float32))
    return cache[key]


def _prepared(images, lights, p_page):
    """derived_inputs.prepare of the page's images → (Features, the derived-image plan)."""
    return prepare(p_page, {c: Source(c, img.bits, img.size, img.has_alpha)
                            for c, img in images.items()}, [lt.kind for lt in lights])


def _variant(images, lights, p, steps, cache):
    """One way to show the painting → (Features of its frame, {shader name: (source, the
    extension each image's sampler wraps with, the images it reads as sRGB codes)}, uniforms,
    textures, warnings). Shaders: 'frame' draws the painting; with shadows it reads each
    light's cos-θ term from a texture (`tex_shadow_<i>`) that the page draws with the
    'shadow_<kind>' shader of that light's kind whenever the light moves (§6; the OSL
    shader's march, pipeline_graph.describe_shadow)."""
    p_page = page_params(p, steps)
    features, plan = _prepared(images, lights, p_page)
    frame = dataclasses.replace(features, shadow_source="baked") if features.shadows \
        else features
    textures, warnings = page_textures(features, plan, p_page, images,
                                       cache.setdefault("images", {}))
    srgb = {c for c, tex in textures.items() if textures.get(tex.get("same_as"), tex)["srgb"]}
    programs = {"frame": glsl_codegen.generate(describe(frame), frame, srgb)}
    if features.shadows:
        programs.update({f"shadow_{kind}": glsl_codegen.generate(describe_shadow(features, kind),
                                                                 features, srgb)
                         for kind in sorted({lt.kind for lt in lights})})
    used = set().union(*(program.uniforms for _, program in programs.values()))
    uniforms = {name: value for name, value in param_uniforms(p_page).items() if name in used}
    if features.shadows:
        uniforms.update(_march_bounds(images, p_page, cache.setdefault("bounds", {})))
    return frame, {name: (src, {"wraps": program.wraps, "codes": sorted(program.codes)})
                   for name, (src, program) in programs.items()}, uniforms, textures, warnings


def page_data(images, lights, p, title="", credits="", steps=None, max_size=None,
              animation=None, turntable_seconds=TURNTABLE_SECONDS, looks=True, frames=None,
              smallest=SMALLEST_LEVEL):
    """Everything the viewer needs, as JSON-ready data → (data, warnings): painting_data's,
    with the smaller copies a device that cannot draw it draws instead (device_fit.py: each
    power of two below its size down to `smallest`; None: none)."""
    def make(side):
        return painting_data(images, lights, p, title, credits, steps, side, animation,
                             turntable_seconds, looks, frames)
    data, warnings = make(max_size)
    return with_levels(data, lambda side: make(side)[0], smallest), warnings


def painting_data(images, lights, p, title="", credits="", steps=None, max_size=None,
                  animation=None, turntable_seconds=TURNTABLE_SECONDS, looks=True, frames=None):
    """Everything the viewer needs to draw the painting at one size, as JSON-ready data.

    images: {channel: ImageData}; lights: [core Light]; p: the parameters. steps: the march's
    K (default the recipe's shadows.steps). max_size: the longest side of the painting in the
    page (images shrink to it). animation: {'fps', 'frames': [[light vectors per light]…]} of
    keyframed lights, played instead of the turntable; turntable_seconds: one turn of the
    key light when the page plays without one.

    Looks: the painting as exported, then each ready-made look (looks.py) that shows it
    differently; looks of other features get a shader of their own, and a look that would
    need an image prepared otherwise than the others is left out.

    frames: a painting that moves (§16) — {'drawings': [{channel: ImageData} of each drawing
    a loop shows], 'sequence': [the drawing of each frame of the loop], 'fps': frames per
    second}; `images` is its first drawing. The page keeps every drawing's images of the
    slots that move (page_frames) and plays them; its other looks are left out.
    """
    images = {c: shrink(img, max_size) for c, img in images.items()}
    looks = looks and frames is None
    cache = {}
    shaders, samplers = [], []

    def shader_indices(sources):
        """{name: index in `shaders`} of a look's shaders, each source stored once (with the
        wrap of each image it lets the GPU filter, in `samplers`)."""
        for src, wraps in sources.values():
            if src not in shaders:
                shaders.append(src)
                samplers.append(wraps)
        return {name: shaders.index(src) for name, (src, _) in sources.items()}
    features, sources, uniforms, textures, warnings = _variant(images, lights, p, steps, cache)
    other_looks = LOOKS.items() if looks else ()
    looks = [{"name": "As exported", "description": "The painting's own settings",
              "shaders": shader_indices(sources), "uniforms": uniforms}]
    for key, (label, description, _) in other_looks:
        _, srcs, u, tex, _ = _variant(images, lights, with_look(p, key), steps, cache)
        if any(c in textures and textures[c] != t for c, t in tex.items()):
            continue
        look = {"name": label, "description": description, "shaders": shader_indices(srcs),
                "uniforms": u}
        if all(look["shaders"] != other["shaders"] or look["uniforms"] != other["uniforms"]
               for other in looks):
            textures.update(tex)
            looks.append(look)
    w, h = images["shape"].size
    return {
        "title": title, "credits": credits, "width": w, "height": h,
        "shaders": [_deflated(src) for src in shaders], "samplers": samplers, "looks": looks,
        "textures": textures,
        "lights": [_light_entry(lt) for lt in lights], "shadows": bool(features.shadows),
        "steps": int(uniforms.get("p_shadows_steps", steps or p.shadows.steps)),
        "turntable_seconds": float(turntable_seconds), "animation": animation,
        "frames": page_frames(frames, images, textures, lights, p, steps, max_size, cache,
                              bool(features.shadows)),
    }, warnings


def page_frames(frames, first, textures, lights, p, steps, max_size, cache, shadows):
    """A painting that moves (§16) in the page → {'fps', 'sequence', 'textures': {channel:
    [its texture in each drawing]} of the images that differ from the first drawing's,
    'uniforms': [the march bounds of each drawing's shape]}, or None for a still one. Each
    drawing's images are prepared as the first's (its derived images too): the page swaps
    them in when the frame changes and draws its shadows again. cache: page_data's, which
    holds what the first drawing's textures and march bounds were made from; shadows: whether
    the page draws them (its first drawing's features say so)."""
    if frames is None:
        return None
    drawings = [first] + [{c: shrink(img, max_size) for c, img in d.items()}
                          for d in frames["drawings"][1:]]
    p_page = page_params(p, steps)
    cells = {c: [textures[c]] for c, tex in textures.items() if "same_as" not in tex}
    bounds = [_march_bounds(first, p_page, cache.setdefault("bounds", {}))] if shadows else []
    for images in drawings[1:]:
        # prepared as the first drawing is (each with a cache of its own): the same kinds
        # of texture, which the page swaps in place of the first's
        features, plan = _prepared(images, lights, p_page)
        made, _ = page_textures(features, plan, p_page, images)
        for c in cells:
            cells[c].append(made[c])
        if shadows:
            bounds.append(_march_bounds(images, p_page, {}))
    return {"fps": float(frames["fps"]), "sequence": list(frames["sequence"]),
            "textures": {c: t for c, t in cells.items() if any(x != t[0] for x in t[1:])},
            "uniforms": bounds or None}


def scene_data(layers, lights, title="", credits="", steps=None, max_size=None,
               turntable_seconds=TURNTABLE_SECONDS, frames=None, animation=None,
               smallest=SMALLEST_LEVEL):
    """A scene of layers (§15) as JSON-ready data → (data, warnings): layers_data's, with the
    smaller copies a device that cannot draw it draws instead (as page_data's)."""
    def make(side):
        return layers_data(layers, lights, title, credits, steps, side, turntable_seconds,
                           frames, animation)
    data, warnings = make(max_size)
    return with_levels(data, lambda side: make(side)[0], smallest), warnings


def layers_data(layers, lights, title="", credits="", steps=None, max_size=None,
                turntable_seconds=TURNTABLE_SECONDS, frames=None, animation=None):
    """A scene of layers (§15) at one size as JSON-ready data → (data, warnings): each layer's
    page data (its own images and shaders, as a painting's, without the other looks), where it lies on
    the canvas, and what the pass of the shadows between layers reads — the layer as the
    layers behind it meet it (alpha, relief, opacity), its surface height, and the pass's
    shader for the number of layers in front of it. The canvas is the back layer's image, at
    most `max_size` pixels on its longer side (every layer shrunk alike). animation: as
    page_data's.

    frames: a scene whose layers move (§16; a Grease Pencil animation, issue 42) — {'scenes':
    [[Layer] of each drawing of the scene one loop shows], 'sequence': [the drawing of each
    frame of the loop], 'fps'}; `layers` is its first drawing, and the layers keep their
    places. A layer whose images change gets its own drawings as a painting that moves does
    (page_frames), with what the shadow pass reads of each; the page swaps them together."""
    canvas = layers[0].images["shape"].pixels.shape[:2]
    factor = 1.0 if not max_size else min(1.0, max_size / max(canvas))
    drawn = [[dataclasses.replace(layer, images={
        c: shrink(img, round(max(img.size) * factor)) for c, img in layer.images.items()})
        for layer in scene_layers]
        for scene_layers in [layers] + list((frames or {}).get("scenes", [])[1:])]
    scene = Scene(drawn[0])
    out, warnings = [], []
    for position, i in enumerate(scene.order):
        layer, place = scene.layers[i], scene.places[i]
        firsts, drawing_of = _distinct([d[i].images for d in drawn])
        moving = None if len(firsts) == 1 else {
            "drawings": [drawn[s][i].images for s in firsts], "fps": frames["fps"],
            "sequence": [drawing_of[s] for s in frames["sequence"]]}
        data, warns = painting_data(layer.images, lights, layer.p, steps=steps, looks=False,
                                    frames=moving)
        warnings += about(layer.name, warns)
        data.update(name=layer.name, place=[place.corner[0], place.corner[1], place.px, place.z])
        # each other drawing of this layer in the first scene, the others as prepared there
        # (what the pass reads of a layer is its own: one drawing prepared at a time)
        reads = [_shadow_pass_reads(scene if s == 0 else Scene(
            [drawn[s][i] if k == i else lay for k, lay in enumerate(drawn[0])],
            prepared={k: r for k, r in scene.ready.items() if k != i}), position,
            data["shadows"]) for s in firsts]
        data.update(reads[0])
        if moving:
            data["frames"].update({k: [r[k] for r in reads] for k in reads[0]})
        front = scene.order[position + 1:]
        if front and data["shadows"]:
            data["through"] = _deflated(through_shader(len(front)))
            data["front"] = [scene.order.index(k) for k in front]
        out.append(data)
    ch, cw = scene.canvas
    return {"title": title, "credits": credits, "width": cw, "height": ch, "layers": out,
            "lights": [_light_entry(lt) for lt in lights],
            "shadows": any(d["shadows"] for d in out),
            "steps": max(d["steps"] for d in out), "looks": [{"name": "As exported"}],
            "turntable_seconds": float(turntable_seconds), "animation": animation,
            "frames": frames and {"fps": float(frames["fps"]),
                                  "sequence": list(frames["sequence"])},
            "layer_quality": {**LAYER_QUALITY["final"], "edge_step": EDGE_STEP}}, warnings


def _distinct(drawings):
    """[{channel: ImageData}] → (the index of each distinct one's first, the distinct one each
    is): two drawings are one when every image is the same or its pixels are equal."""
    firsts, of = [], []
    for images in drawings:
        same = next((k for k, j in enumerate(firsts) if all(
            drawings[j][c] is img or np.array_equal(drawings[j][c].pixels, img.pixels)
            for c, img in images.items())), None)
        if same is None:
            same = len(firsts)
            firsts.append(len(of))
        of.append(same)
    return firsts, of


def _shadow_pass_reads(scene, position, shadows):
    """What the pass of the shadows between layers reads of the layer at `position` (back
    first) in `scene`: as an occluder of the layers behind it ('occluder', 'slab'), and as a
    receiver of those in front ('surface', where its rays start; `shadows`: it has any)."""
    i = scene.order[position]
    reads = {}
    if position:
        occ = scene.occluder(i)
        (h, w) = scene.ready[i].size
        reads["occluder"] = encode_pixels(np.dstack([occ.alpha, occ.relief_px, occ.opacity,
                                                     np.zeros_like(occ.alpha)]), "f32")
        reads["slab"] = [occ.bottom, occ.top, float(w), float(h)]
    if position + 1 < len(scene.order) and shadows:
        reads["surface"] = encode_pixels(scene_surface(scene, i)[..., None], "f32")
    return reads


def scene_surface(scene, i):
    """Layer i's surface height above its plane (canvas pixels) at each of its pixels: where
    the rays of the shadows between layers start (§15)."""
    z = scene.ready[i].z_px
    h, w = scene.ready[i].size
    return np.zeros((h, w), np.float32) if z is None else \
        np.nan_to_num(np.asarray(z, np.float32)) * np.float32(scene.places[i].px)


def through_shader(n):
    """The fragment shader of the pass of the shadows between layers for a layer with `n`
    layers in front (snippets/glsl/dp_layers.glsl, and its dp_front for them)."""
    uniforms = "".join(f"uniform sampler2D dp_occ{k};\nuniform vec4 dp_occ_place{k};\n"
                       f"uniform vec4 dp_occ_slab{k};\n" for k in range(n))
    calls = "".join(f"    t *= 1.0 - dp_layer(dp_occ{k}, dp_occ_place{k}, dp_occ_slab{k}, o, d, "
                    f"len);\n" for k in range(n))
    return ("#version 300 es\n" + read_snippet("glsl", "dp_layers.glsl") + "\n" + uniforms +
            "float dp_front(vec3 o, vec3 d, float len)\n{\n    float t = 1.0;\n" + calls +
            "    return t;\n}\n")


def _deflated(text):
    """A shader's source deflated and base64-coded (the viewer inflates it as it inflates the
    images): shader text is most of a small painting's page."""
    return base64.b64encode(zlib.compress(text.encode("utf-8"), 9)).decode("ascii")


def _asset(name):
    with open(os.path.join(HERE, name), encoding="utf-8") as fh:
        return fh.read()


# Characters the HTML parser reads inside a <script> data block (`</script`, `<!--`, and a
# `<script` after it, which make the parser swallow the viewer's own script: issue 60),
# written as JSON escapes that JSON.parse turns back into them
HTML_SAFE = {"<": "\\u003c", ">": "\\u003e", "&": "\\u0026"}


def json_for_html(data):
    """`data` as JSON that no string in it can end or hide the <script> block it sits in.

    >>> json_for_html({"name": "<!--<script>"})
    '{"name":"\\\\u003c!--\\\\u003cscript\\\\u003e"}'
    """
    text = json.dumps(data, separators=(",", ":"))
    for char, escape in HTML_SAFE.items():
        text = text.replace(char, escape)
    return text


DATA_START, DATA_END = 'id="dp-data">', "</script>"     # viewer.html's data block


def data_of_page(text):
    """The data a page's text carries (render_html's, read back): what a script or a test
    reads of an exported page.

    >>> data_of_page(render_html({"title": "</script>", "lights": []}))["title"]
    '</script>'
    """
    return json.loads(text.split(DATA_START, 1)[1].split(DATA_END, 1)[0])


def render_html(data):
    """The page's text: viewer.html with its style, script and data inlined."""
    payload = json_for_html(data)
    title = html.escape(data["title"] or "Dynamic painting")
    return (_asset("viewer.html").replace("{{title}}", title)
            .replace("{{style}}", _asset("viewer.css"))
            .replace("{{script}}", _asset("viewer.js"))
            .replace("{{data}}", payload))


def write_page(path, data):
    """Write the page → its size in bytes."""
    text = render_html(data)
    write_text_whole(path, text)            # whole or not at all (issue 60)
    return len(text.encode("utf-8"))
