"""The compositor flavour of the graph's backend-specific nodes (graph.py).

The same description (pipeline_graph.describe) becomes a compositor node group: the channel
images, every live parameter and each light (vector, colour, strength, baked cos-θ image)
are group inputs, so they can be keyframed, driven or fed by other nodes; the outputs are the
painting (premultiplied RGBA) and its passes. Image lookups are Map UV nodes (UV z = 1, the
node multiplies its result by it, blender-notes.md); the pixel's own UV is the shape image's
normalized coordinates (pixel centres).

Inputs differ from the material's in documented ways: images arrive colour-managed by their
Image nodes (set shape, gloss, transparency and shadow images to Non-Color, and images with
alpha to Channel Packed); the height map is used as given (an 8-bit one wants the §2 pre-blur
first); environment and background are used unblurred (for glossy/translucent looks, feed
blurred copies, e.g. made by the add-on).
"""
from ... import params
from .build import link_or_set

# channel of the description → group input it reads (the pre-blurred height map comes in
# through the Shape input); the background outside the silhouette has an input of its own, as
# the Background input may be a blurred copy (translucent looks, §11)
INPUT_OF = {"height": "shape"}
SHARP_BACKGROUND = ("background shown outside the silhouette, unblurred (the same image as "
                    "Background, or its sharp original when Background is blurred)", "colour")
EXTENSIONS = {"REPEAT": "Repeat", "EXTEND": "Extend", "MIRROR": "Extend"}
INTERPOLATIONS = {"Linear": "Bilinear", "Closest": "Nearest"}


def input_name(channel):
    return channel.replace("_", " ").title()


def param_inputs(param, value):
    """A parameter's group inputs and their values: [(name, number)], two for a vec2
    ('Reflection offset x', 'Reflection offset y'); 'auto' feeds 1 (the Features resolve it)."""
    label = f"{param.section.title()} {param.key.replace('_', ' ')}"
    if param.kind == "vec2":
        return [(f"{label} {axis}", float(c)) for axis, c in zip("xy", value)]
    return [(label, 1.0 if value == "auto" else float(value))]


class CompositorBackend:
    prefix = "Compositor "      # node groups are typed: keep them apart from the material's

    def __init__(self, silhouette="", light_kinds=(), size=(1, 1)):
        self.silhouette = silhouette        # 'shape' or 'dark': whose alpha cuts out
        self.light_kinds = light_kinds
        self.image_size = size              # the shape image's (width, height)
        self._inputs = None
        self._uv = None

    # -- interface ----------------------------------------------------------------------
    def _socket(self, tree, name, kind, default=None, lo=None, hi=None, description=""):
        """The group input `name` (created on first use) → its output socket on the input node."""
        if name not in [s.name for s in tree.interface.items_tree if s.item_type == "SOCKET"
                        and s.in_out == "INPUT"]:
            sock = tree.interface.new_socket(name, in_out="INPUT", socket_type=kind,
                                             description=description)
            if default is not None:
                sock.default_value = default
            if lo is not None:
                sock.min_value, sock.max_value = lo, hi
        if self._inputs is None:
            self._inputs = tree.nodes.new("NodeGroupInput")
            self._inputs.label = "Images, parameters and lights"
        return self._inputs.outputs[name]

    def _image(self, tree, channel):
        channel = self.silhouette if channel == "silhouette" else INPUT_OF.get(channel, channel)
        if channel.startswith("shadow_"):
            i = int(channel.split("_")[1])
            return self._socket(tree, f"Light {i + 1} Shadow", "NodeSocketColor",
                                description="Its baked cos-θ term (pipeline.md §6), Non-Color")
        what, kind = SHARP_BACKGROUND if channel == "background_sharp" else \
            params.CHANNELS[channel]
        return self._socket(tree, input_name(channel), "NodeSocketColor",
                            description=f"{what[0].upper()}{what[1:]} ({kind})")

    # -- pseudo nodes -------------------------------------------------------------------
    def uv(self, tree, node, inputs):
        coords = tree.nodes.new("CompositorNodeImageCoordinates")
        tree.links.new(self._image(tree, "shape"), coords.inputs["Image"])
        self._uv = coords.outputs["Normalized"]
        return [coords], {0: self._uv}

    def size(self, tree, node, inputs):
        """The image size as numbers: a group is built for one size (its features)."""
        width, height = (float(n) for n in self.image_size)
        return [], {"width": width, "height": height}

    def sample(self, tree, node, inputs):
        channel = node.props["channel"]
        made = []
        uv = inputs.get("uv", self._uv)
        extension = node.props["extension"]
        if extension == "MIRROR":        # Map UV has no mirror: fold the UV (ping-pong)
            fold = []
            sep = tree.nodes.new("ShaderNodeSeparateXYZ")
            tree.links.new(uv, sep.inputs[0])
            for axis in (0, 1):
                m = tree.nodes.new("ShaderNodeMath")
                m.operation = "PINGPONG"
                tree.links.new(sep.outputs[axis], m.inputs[0])
                m.inputs[1].default_value = 1.0
                fold.append(m)
            comb = tree.nodes.new("ShaderNodeCombineXYZ")
            tree.links.new(fold[0].outputs[0], comb.inputs[0])
            tree.links.new(fold[1].outputs[0], comb.inputs[1])
            uv = comb.outputs[0]
            made += [sep, *fold, comb]
        lift = tree.nodes.new("ShaderNodeVectorMath")     # z = 1: Map UV scales by UV.z
        lift.operation = "MULTIPLY_ADD"
        tree.links.new(uv, lift.inputs[0])
        lift.inputs[1].default_value = (1.0, 1.0, 0.0)
        lift.inputs[2].default_value = (0.0, 0.0, 1.0)
        lookup = tree.nodes.new("CompositorNodeMapUV")
        tree.links.new(self._image(tree, channel), lookup.inputs["Image"])
        tree.links.new(lift.outputs[0], lookup.inputs["UV"])
        lookup.inputs["Interpolation"].default_value = INTERPOLATIONS[node.props["interpolation"]]
        lookup.inputs["Extension X"].default_value = EXTENSIONS[extension]
        lookup.inputs["Extension Y"].default_value = EXTENSIONS[extension]
        split = tree.nodes.new("CompositorNodeSeparateColor")
        tree.links.new(lookup.outputs[0], split.inputs[0])
        color = lookup.outputs[0]
        made += [lift, lookup, split]
        if channel in ("environment", "background", "background_sharp"):
            # the core looks these up premultiplied (core.pipeline.lookup_copy); the painted
            # images are used straight. Inputs are Channel Packed (alpha kept apart).
            spread = tree.nodes.new("ShaderNodeCombineXYZ")
            for i in range(3):
                tree.links.new(split.outputs["Alpha"], spread.inputs[i])
            times = tree.nodes.new("ShaderNodeVectorMath")
            times.operation = "MULTIPLY"
            tree.links.new(color, times.inputs[0])
            tree.links.new(spread.outputs[0], times.inputs[1])
            color = times.outputs[0]
            made += [spread, times]
        return made, {"color": color, "alpha": split.outputs["Alpha"]}

    def param(self, tree, node, inputs):
        param = params.BY_PATH[node.props["path"]]
        name, default = param_inputs(param, param.default)[node.props.get("index") or 0]
        unit = f" ({param.unit})" if param.unit else ""
        sock = self._socket(tree, name, "NodeSocketFloat", default,
                            param.min if param.min is not None else -1e9,
                            param.max if param.max is not None else 1e9,
                            f"{param.help}{unit}. pipeline.md {param.spec}")
        return [], {0: sock}

    def light(self, tree, node, inputs):
        i, kind = node.props["index"], node.props["kind"]
        what = "direction toward the light" if kind == "sun" else "position (image widths)"
        vec = self._socket(tree, f"Light {i + 1} {'Direction' if kind == 'sun' else 'Position'}",
                           "NodeSocketVector", description=f"{kind.title()}: {what}, painting frame")
        colour = self._socket(tree, f"Light {i + 1} Color", "NodeSocketColor", (1.0, 1.0, 1.0, 1.0),
                              description="Linear RGB colour of the light")
        strength = self._socket(tree, f"Light {i + 1} Strength", "NodeSocketFloat", 1.0, 0.0, 1e6,
                                "k of pipeline.md §5")
        weight = tree.nodes.new("ShaderNodeVectorMath")
        weight.operation = "SCALE"
        weight.label = f"Light {i + 1} k·c"
        tree.links.new(colour, weight.inputs[0])
        tree.links.new(strength, weight.inputs["Scale"])
        return [weight], {"vector": vec, "weight": weight.outputs[0]}

    def output(self, tree, node, inputs):
        per_light = sorted(k[5:] for k in inputs if k.startswith("pass:t"))
        outputs = [("Image", "NodeSocketColor"), ("Weight W", "NodeSocketColor"),
                   ("Specular s", "NodeSocketColor"), ("Fresnel F", "NodeSocketFloat")] + \
            [(f"Light {k[1:]} t", "NodeSocketFloat") for k in per_light]
        existing = [s.name for s in tree.interface.items_tree if s.item_type == "SOCKET"
                    and s.in_out == "OUTPUT"]
        for name, kind in outputs:
            if name not in existing:
                tree.interface.new_socket(name, in_out="OUTPUT", socket_type=kind)
        out = tree.nodes.new("NodeGroupOutput")
        rgba = tree.nodes.new("CompositorNodeCombineColor")
        sep = tree.nodes.new("ShaderNodeSeparateXYZ")
        link_or_set(tree, inputs["rgb"], sep.inputs[0])
        for i in range(3):
            tree.links.new(sep.outputs[i], rgba.inputs[i])
        link_or_set(tree, inputs["alpha"], rgba.inputs["Alpha"])
        tree.links.new(rgba.outputs[0], out.inputs["Image"])
        names = {"pass:W": "Weight W", "pass:s": "Specular s", "pass:F": "Fresnel F",
                 **{f"pass:{k}": f"Light {k[1:]} t" for k in per_light}}
        for key, name in names.items():
            link_or_set(tree, inputs.get(key, 0.0), out.inputs[name])
        return [sep, rgba, out], {}

