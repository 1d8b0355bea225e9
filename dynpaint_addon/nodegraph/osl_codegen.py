"""OSL source from the graph description: the pipeline as one Cycles Script node (issue 5).

The third backend of pipeline_graph.describe, and a textual one: every node becomes an OSL
statement with Blender's own node semantics (text_codegen.py, shared with the web page's
GLSL), every sub-graph an OSL function, image lookups
`texture()` calls on files, parameters and lights shader parameters (the add-on drives them
like the material's sockets). The cos-θ term can come from a baked image or from the march in
`nodegraph/snippets/shared/cos_theta.h`, evaluated per shading point (no bake).

No bpy here: the text can be generated and inspected anywhere.
"""
from .graph import FLOAT, VECTOR
from .text_codegen import Emitter, Program, ident, indent, param_name, read_snippet

WRAPS = {"REPEAT": "periodic", "EXTEND": "clamp", "MIRROR": "mirror"}
INTERPS = {"Linear": "linear", "Closest": "closest"}


class OslEmitter(Emitter):
    """The graph's nodes as OSL statements (text_codegen.Emitter) and its pseudo nodes."""

    # -- backend-specific ---------------------------------------------------------------
    def op_dp_uv(self, n):
        self.define(n, 0, VECTOR, "dp_uv()")

    def op_dp_sample(self, n):
        channel = n.props["channel"]
        uv = self.ref(n.inputs["uv"], VECTOR) if "uv" in n.inputs else "dp_uv()"
        if channel.startswith("shadow_") and self.program.march:
            self.define(n, "color", VECTOR, "vector({})".format(self.program.march_call(
                self.ref(n.inputs["normal"], VECTOR), self.ref(n.inputs["light"], VECTOR),
                n.props["kind"], uv)))
            self.define(n, "alpha", FLOAT, "1.0")
            return
        image, srgb = self.program.image_arguments(channel)
        self.lines.append(f"float n{n.id}_a;")
        self.define(n, "color", VECTOR,
                    f'dp_tex({image}, {srgb}, {uv}, "{WRAPS[n.props["extension"]]}", '
                    f'"{INTERPS[n.props["interpolation"]]}", n{n.id}_a)')
        self.bind(n, "alpha", FLOAT, f"n{n.id}_a")

    def op_dp_param(self, n):
        self.bind(n, 0, FLOAT, self.program.param(n.props["path"], n.props.get("index")))

    def op_dp_light(self, n):
        i, kind = n.props["index"], n.props["kind"]
        self.program.light(i, kind)
        space = "vector" if kind == "sun" else "point"
        self.define(n, "vector", VECTOR, f'transform("world", "object", {space}(light{i + 1}_world))')
        self.define(n, "weight", VECTOR, f"vector(light{i + 1}_color) * light{i + 1}_strength")

    def op_dp_output(self, n):
        self.lines.append(f"Color = color({self.ref(n.inputs['rgb'], VECTOR)});")
        self.lines.append(f"Alpha = {self.ref(n.inputs['alpha'])};")
        for key, value in n.inputs.items():
            if key.startswith("pass:") and key[5:] in ("W", "s", "F"):
                name = key[5:]
                kind = FLOAT if name == "F" else VECTOR
                expr = self.ref(value, kind)
                self.lines.append(f"Pass_{name} = {'color(' + expr + ')' if kind == VECTOR else expr};")


class OslProgram(Program):
    """The whole shader: helpers, one function per sub-graph, parameters, body."""

    def __init__(self, features, march=False):
        super().__init__(features)
        self.march = march

    def param(self, path, index=None):
        name = param_name(path, index)
        self.params.setdefault(name, f"float {name} = 0.0")
        return name

    def image(self, channel):
        name = ident(channel)
        self.params.setdefault(name + "_file", f'string {name}_file = ""')
        self.params.setdefault(name + "_srgb", f"int {name}_srgb = 0")
        # its size in texels: dp_tex wraps texel indices itself (snippets/osl/dp_tex.h)
        self.params.setdefault(name + "_width", f"int {name}_width = 1")
        self.params.setdefault(name + "_height", f"int {name}_height = 1")
        return name

    def image_arguments(self, channel):
        """An image as dp_tex and the march read it (a dp_image) and its sRGB flag."""
        name = self.image(channel)
        return f"dp_image({name}_file, {name}_width, {name}_height)", f"{name}_srgb"

    def bound(self, name):
        self.params.setdefault(name, f"float {name} = 0.0")
        return name

    def light(self, i, kind):
        n = i + 1
        self.params.setdefault(f"light{n}_world", f"vector light{n}_world = vector(0.0, 0.0, 1.0)")
        self.params.setdefault(f"light{n}_color", f"color light{n}_color = color(1.0)")
        self.params.setdefault(f"light{n}_strength", f"float light{n}_strength = 1.0")


def generate(graph, features, march=False, name="dynamic_painting", texture_t_down=False):
    """OSL source of the whole pipeline for `features` (graph = describe(features)).

    march: compute the cos-θ term in the shader (nodegraph/snippets/shared/cos_theta.h) instead of
    reading baked images. texture_t_down: for a Cycles whose texture() counts t down the image
    (Blender 5.0 and 5.1; snippets/osl/dp_tex.h).
    """
    prog = OslProgram(features, march)
    body = OslEmitter(graph, prog).emit()
    params = ["vector painting_uv = vector(0.0)"] + list(prog.params.values()) + [
        "output color Color = 0", "output float Alpha = 1", "output color Pass_W = 0",
        "output color Pass_s = 0", "output float Pass_F = 0"]
    functions = "\n".join(src for _, src in prog.functions.values())
    march_src = ""
    if march and features.shadows:
        march_src = prog.march_source()
    head = ("// Generated by dynpaint_addon/nodegraph/osl_codegen.py from the pipeline's graph\n"
            "// description (pipeline.md §2–§11); do not edit: regenerate.\n"
            f"// Features: {features.key()}\n#include \"stdosl.h\"\n\n"
            + ("#define DP_TEXTURE_T_DOWN 1\n\n" if texture_t_down else ""))
    return (head + read_snippet("shared", "dp_nodes.h") + "\n" + read_snippet("osl", "dp_tex.h") + "\n"
            + functions + "\n" + march_src
            + f"shader {name}(\n" + ",\n".join("    " + p for p in params) + ")\n{\n"
            + indent(body) + "}\n")
