"""A page that fits the device it is opened on (issue 62): smaller copies of a large painting.

WebGL2 promises textures of 2048 pixels a side and no more (many phones stop at 4096), and it
says nothing of memory; five 8192² RGBA textures are over 1 GB. A page whose painting is
larger than SMALLEST_LEVEL carries the same page at each power of two below it, down to
SMALLEST_LEVEL — each made as the painting's own page is, from its images shrunk to that size
(so each is what the core draws at that size) — and every copy says what it needs (`fit`):
its largest texture side and an estimate of its GPU memory. The viewer (viewer.js,
chooseLevel; chosen_copy here) reads the device's MAX_TEXTURE_SIZE and a memory budget (a
share of the device's memory) at load and draws the largest copy that fits. The copies add about a third to the file (¼ + 1/16 + …).

>>> level_sides(8192)
[4096, 2048]
>>> level_sides(3000), level_sides(2048), level_sides(256, smallest=64)
([2048], [], [128, 64])
"""
SMALLEST_LEVEL = 2048            # every WebGL2 device draws textures of this side (its spec)
# a page's painting is at most this long unless asked (export-web --max-size, the add-on's Max
# Size): many phones draw textures this large and no larger, and its page is a few MB
# (web-numbers.md, "On a phone")
DEFAULT_MAX_SIZE = 4096
# the share of the device's memory (navigator.deviceMemory: browsers round it and cap it at
# 8 GB, and say nothing in some; 8 then) a copy's textures may take
GPU_SHARE = 0.25
UNREPORTED_GB = 8

# GPU bytes per texel of a page's stored texture formats as the viewer uploads them (RGBA:
# 8-bit codes as RGBA8, 16-bit codes decoded to RGBA32F, halves RGBA16F, floats RGBA32F)
TEXEL_BYTES = {"u8": 4, "u16": 16, "f16": 8, "f32": 16}
# a light's shadow targets (R32F): its own term, and for a layer with layers in front the
# product and the antialiasing pass's centres
SHADOW_TARGET_BYTES = 4
CANVAS_BYTES = 16                # a scene's composite (RGBA32F) at the canvas's size


def level_sides(side, smallest=SMALLEST_LEVEL):
    """The long sides of the smaller copies a page of a painting `side` pixels long carries:
    each power of two below `side`, down to `smallest`."""
    sides, s = [], 1
    while s * 2 < side:
        s *= 2
    while s >= smallest and s < side:
        sides.append(s)
        s //= 2
    return sides


def _textures(node, seen):
    """Every stored texture (a dict with 'format' and 'data') in page data, each once."""
    if isinstance(node, dict):
        if "format" in node and "data" in node:
            if id(node) not in seen:
                seen.add(id(node))
                yield node
            return
        for value in node.values():
            yield from _textures(value, seen)
    elif isinstance(node, list):
        for value in node:
            yield from _textures(value, seen)


def _shadow_bytes(painting, lights):
    """Bytes of one painting's (or layer's) shadow targets: one per light, three where the
    layers in front shadow it (viewer.js shadowTarget, drawThrough)."""
    if not painting.get("shadows"):
        return 0
    targets = 3 if painting.get("through") else 1
    return painting["width"] * painting["height"] * SHADOW_TARGET_BYTES * targets * lights


def fit_of(data):
    """What drawing a page's data needs of a device: {'side': its largest texture's longer
    side (the canvas's, for a scene), 'bytes': its GPU memory, estimated from its textures,
    shadow targets and a scene's composite}."""
    textures = list(_textures(data, set()))
    side = max((max(t["width"], t["height"]) for t in textures), default=0)
    n = len(data["lights"])
    paintings = data.get("layers") or [data]
    estimate = sum(t["width"] * t["height"] * TEXEL_BYTES[t["format"]] for t in textures)
    estimate += sum(_shadow_bytes(d, n) for d in paintings)
    if "layers" in data:
        side = max(side, data["width"], data["height"])
        estimate += data["width"] * data["height"] * CANVAS_BYTES
    return {"side": side, "bytes": int(estimate)}


def chosen_copy(data, max_texture, device_gb=None):
    """The copy of a page (its data, or one of its `smaller`) a device draws: the largest
    whose textures are at most `max_texture` pixels a side and whose memory is within
    GPU_SHARE of `device_gb` — else the smallest. The viewer's rule (viewer.js chooseLevel),
    for reports; the tests hold the two to each other."""
    budget = (device_gb or UNREPORTED_GB) * 2 ** 30 * GPU_SHARE
    copies = [data] + data.get("smaller", [])
    return next((d for d in copies if d["fit"]["side"] <= max_texture
                 and d["fit"]["bytes"] <= budget), copies[-1])


def with_levels(data, make, smallest=SMALLEST_LEVEL):
    """`data` (a page's) with its `fit` and `smaller`: the page made by `make(max_size)` at
    each of level_sides, each with its own `fit`, largest first (and chosen_copy's constants,
    `device_rule`, for the viewer's twin of it). smallest: None for none."""
    data["fit"] = fit_of(data)
    data["device_rule"] = {"gpu_share": GPU_SHARE, "unreported_gb": UNREPORTED_GB}
    data["smaller"] = []
    if smallest is None:
        return data
    for side in level_sides(max(data["width"], data["height"]), smallest):
        level = make(side)
        level["fit"] = fit_of(level)
        data["smaller"].append(level)
    return data
