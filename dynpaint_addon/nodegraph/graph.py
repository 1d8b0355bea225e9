"""A backend-neutral node graph: the one description of the pipeline's node trees.

The pipeline (pipeline_graph.py) is written once against this small API; `blender/nodes/build.py`
turns a Graph into a Blender shader material tree or a compositor node group. Ordinary nodes
are named by their Blender class (ShaderNodeMath, ShaderNodeVectorMath, ShaderNodeMapRange,
ShaderNodeMix, ShaderNodeCombineXYZ, ShaderNodeSeparateXYZ), which exist with the same sockets
in shader and compositor trees (blender-notes.md). Only a few operations are backend specific
and are written as pseudo nodes with a `dp.` prefix:

  dp.uv       the painting's UV (u, v, 0), u, v ∈ [0, 1] over the painting
  dp.size     the shape image's width and height in pixels (Values set in place vs numbers)
  dp.sample   an input image looked up at a UV (Image Texture vs Map UV)  → color, alpha
  dp.param    a parameter of params.py, or one component of it (a driven Value vs a group input)
  dp.light    a light's vector in the painting frame and its k·c weight (§5)
  dp.output   the premultiplied result (rgb, alpha)
  dp.group    a reusable sub-graph, built once as a node group

No bpy import: a Graph is plain data, so it can be inspected and tested without Blender.
"""
from contextlib import contextmanager
from dataclasses import dataclass, field

FLOAT, VECTOR = "FLOAT", "VECTOR"


@dataclass(frozen=True)
class Ref:
    """An output socket: node id and output identifier (or index)."""
    node: int
    output: object = 0


@dataclass
class Node:
    id: int
    op: str
    props: dict = field(default_factory=dict)
    inputs: dict = field(default_factory=dict)   # socket identifier or index → Ref | constant
    label: str = ""
    section: str = ""


@dataclass(frozen=True)
class Bilinear:
    """A lookup Graph.sample_bilinear built: its image, where (u, v), how it wraps, the nodes
    that make it (four Closest taps and their weights) and its outputs. A backend whose
    lookups are exact bilinear filters without mipmaps (the web page's textureLod) may read it
    in one fetch instead of those nodes."""
    channel: str
    u: object
    v: object
    extension: str
    nodes: range
    color: Ref
    alpha: Ref


# Output identifiers of the nodes whose first output is not the one we want.
VMATH_VALUE_OPS = {"DOT_PRODUCT", "LENGTH", "DISTANCE"}


class Graph:
    """Nodes in creation order (always topological: inputs exist before their users)."""

    def __init__(self, name="", inputs=(), outputs=()):
        self.name = name
        self.nodes = []
        self.bilinears = []     # sample_bilinear's lookups (a backend may filter them itself)
        self.inputs = list(inputs)     # group interface: [(name, FLOAT|VECTOR)]
        self.outputs = list(outputs)
        self._section = ""

    # -- plumbing -----------------------------------------------------------------------
    def add(self, op, inputs=None, label="", **props):
        """A new node after every other; its inputs may only name earlier nodes (what keeps
        the order topological, so every backend builds in one pass)."""
        inputs = dict(inputs or {})
        late = [ref for ref in inputs.values()
                if isinstance(ref, Ref) and not 0 <= ref.node < len(self.nodes)]
        if late:
            raise ValueError(f"{self.name or 'graph'}: {op} reads node {late[0].node}, which "
                             f"does not come before it (nodes 0 … {len(self.nodes) - 1})")
        node = Node(len(self.nodes), op, props, inputs, label, self._section)
        self.nodes.append(node)
        return node

    @contextmanager
    def section(self, title):
        """Nodes created inside belong to `title` (a frame in the built tree)."""
        old, self._section = self._section, title
        try:
            yield
        finally:
            self._section = old

    def group_input(self, name):
        """Inside a sub-graph: the group input socket `name`."""
        node = next((n for n in self.nodes if n.op == "dp.group_input"), None) \
            or self.add("dp.group_input")
        return Ref(node.id, name)

    def set_outputs(self, **refs):
        """Inside a sub-graph: connect the group outputs (names as declared)."""
        self.add("dp.group_output", refs)

    # -- ordinary nodes -----------------------------------------------------------------
    def math(self, operation, a, b=0.0, c=0.0, clamp=False, label=""):
        n = self.add("ShaderNodeMath", {0: a, 1: b, 2: c}, label, operation=operation,
                     use_clamp=clamp)
        return Ref(n.id, 0)

    def vmath(self, operation, a, b=(0.0, 0.0, 0.0), c=(0.0, 0.0, 0.0), scale=1.0, label=""):
        n = self.add("ShaderNodeVectorMath", {0: a, 1: b, 2: c, 3: scale}, label,
                     operation=operation)
        return Ref(n.id, 1 if operation in VMATH_VALUE_OPS else 0)

    def separate(self, v, label=""):
        n = self.add("ShaderNodeSeparateXYZ", {0: v}, label)
        return Ref(n.id, 0), Ref(n.id, 1), Ref(n.id, 2)

    def combine(self, x=0.0, y=0.0, z=0.0, label=""):
        return Ref(self.add("ShaderNodeCombineXYZ", {0: x, 1: y, 2: z}, label).id, 0)

    def map_range(self, value, from_min, from_max, to_min=0.0, to_max=1.0,
                  interpolation="LINEAR", clamp=True, label=""):
        n = self.add("ShaderNodeMapRange", {"Value": value, "From Min": from_min,
                                            "From Max": from_max, "To Min": to_min,
                                            "To Max": to_max},
                     label, data_type="FLOAT", interpolation_type=interpolation, clamp=clamp)
        return Ref(n.id, "Result")

    def mix_float(self, factor, a, b, label=""):
        """a + (b − a)·factor, factor clamped to [0, 1]."""
        n = self.add("ShaderNodeMix", {"Factor_Float": factor, "A_Float": a, "B_Float": b},
                     label, data_type="FLOAT", clamp_factor=True)
        return Ref(n.id, "Result_Float")

    def mix_vector(self, factor, a, b, label=""):
        """Per-channel a + (b − a)·factor: factor a vector (NON_UNIFORM) or a float."""
        n = self.add("ShaderNodeMix", {"Factor_Vector": factor, "A_Vector": a, "B_Vector": b},
                     label, data_type="VECTOR", factor_mode="NON_UNIFORM", clamp_factor=True)
        return Ref(n.id, "Result_Vector")

    # -- pseudo nodes (backend specific) ------------------------------------------------
    def uv(self):
        return Ref(self.add("dp.uv", label="UV").id, 0)

    def image_size(self):
        """The shape image's (width, height) in pixels → two float refs. A value of the built
        tree, not its structure: a painting framed anew at another size keeps its tree
        (blender/material/tree.rebuild_tree sets them in place)."""
        n = self.add("dp.size")          # (a backend labels its two values)
        return Ref(n.id, "width"), Ref(n.id, "height")

    def sample(self, channel, uv=None, extension="EXTEND", label="", interpolation="Linear"):
        """Look `channel` up at uv (default: the pixel's own UV) → (color, alpha) refs."""
        n = self.add("dp.sample", {"uv": uv} if uv is not None else {}, label or channel,
                     channel=channel, extension=extension, interpolation=interpolation)
        return Ref(n.id, "color"), Ref(n.id, "alpha")

    def shadow_term(self, index, kind, normal, light):
        """The raw cos-θ term of light `index` (§6) → float ref. Node trees read the image
        numpy baked ('shadow_<index>'); the OSL backend marches in the shader from the normal
        and the light vector given here."""
        n = self.add("dp.sample", {"normal": normal, "light": light}, f"cos-θ shadow {index + 1}",
                     channel=f"shadow_{index}", extension="EXTEND", interpolation="Linear",
                     kind=kind)
        return self.separate(Ref(n.id, "color"))[0]

    def sample_bilinear(self, channel, u, v, size, extension="EXTEND"):
        """Bilinear lookup built from four texel-exact (Closest) taps → (color, alpha).

        GPU filtering picks a mipmap level from the UV derivatives, so a warped lookup that
        compresses the image comes out blurred in EEVEE (0.1 off at total internal
        reflection); four Closest taps and explicit weights are core.sampling.sample_bilinear
        in every backend. size: the image's (width, height) in pixels.
        """
        w, h = size
        first = len(self.nodes)
        x = self.math("MULTIPLY_ADD", u, float(w), -0.5, label="x − ½")
        y = self.math("MULTIPLY_ADD", v, float(h), -0.5, label="y − ½")
        x0, y0 = self.math("FLOOR", x), self.math("FLOOR", y)
        fx, fy = self.math("SUBTRACT", x, x0), self.math("SUBTRACT", y, y0)
        u0 = self.math("MULTIPLY", self.math("ADD", x0, 0.5), 1.0 / w)
        v0 = self.math("MULTIPLY", self.math("ADD", y0, 0.5), 1.0 / h)
        u1, v1 = self.math("ADD", u0, 1.0 / w), self.math("ADD", v0, 1.0 / h)
        taps = {(i, j): self.sample(channel, self.combine(uu, vv), extension,
                                    f"{channel} texel {i}{j}", "Closest")
                for i, vv in ((0, v0), (1, v1)) for j, uu in ((0, u0), (1, u1))}
        fxv = self.combine(fx, fx, fx)
        fyv = self.combine(fy, fy, fy)
        bottom = self.mix_vector(fxv, taps[0, 0][0], taps[0, 1][0])
        top = self.mix_vector(fxv, taps[1, 0][0], taps[1, 1][0])
        alpha = self.mix_float(fy, self.mix_float(fx, taps[0, 0][1], taps[0, 1][1]),
                               self.mix_float(fx, taps[1, 0][1], taps[1, 1][1]))
        color = self.mix_vector(fyv, bottom, top, label=f"{channel} (bilinear)")
        self.bilinears.append(Bilinear(channel, u, v, extension, range(first, len(self.nodes)),
                                       color, alpha))
        return color, alpha

    def param(self, path, label="", index=None):
        """A scalar parameter of params.py (e.g. 'diffuse.t0'), or component `index` of a
        two-number one (reflection.offset), live in the built tree."""
        props = {"path": path} if index is None else {"path": path, "index": index}
        return Ref(self.add("dp.param", label=label or path + ("" if index is None else
                                                                  f"[{index}]"), **props).id, 0)

    def light(self, index, kind):
        """Light `index` (a sun or a point light) → (vector, k·c weight) refs.

        vector: the sun's direction toward the light, or the point light's position, in the
        painting frame (image widths from the painting's centre, §0 and core/lights.py).
        """
        n = self.add("dp.light", label=f"Light {index + 1} ({kind})", index=index, kind=kind)
        return Ref(n.id, "vector"), Ref(n.id, "weight")

    def output(self, rgb, alpha, passes=None):
        """The result: premultiplied rgb and alpha, and named passes a backend may expose."""
        self.add("dp.output", {"rgb": rgb, "alpha": alpha, **{f"pass:{k}": v for k, v in
                                                              (passes or {}).items()}}, "Painting")

    def group(self, sub, inputs, label=""):
        """Instantiate sub-graph `sub` (a Graph with declared inputs/outputs) → {output: Ref}."""
        n = self.add("dp.group", inputs, label or sub.name, graph=sub)
        return {name: Ref(n.id, name) for name, _ in sub.outputs}

    # -- queries ------------------------------------------------------------------------
    def count(self, recursive=True):
        """Number of nodes as built (group contents counted once per group when recursive)."""
        total, seen = 0, set()

        def walk(g):
            nonlocal total
            for n in g.nodes:
                total += 1
                sub = n.props.get("graph")
                if recursive and sub is not None and sub.name not in seen:
                    seen.add(sub.name)
                    walk(sub)
        walk(self)
        return total

    def ops(self):
        """Every op used, recursively (for tests: 'is there a refraction branch?')."""
        found = set()

        def walk(g):
            for n in g.nodes:
                found.add(n.op)
                if n.op == "dp.group":
                    found.add("group:" + n.props["graph"].name)
                    walk(n.props["graph"])
        walk(self)
        return found

    def channels(self):
        return {n.props["channel"] for n in self.nodes if n.op == "dp.sample"}

    def params(self):
        return {n.props["path"] for n in self.nodes if n.op == "dp.param"}
