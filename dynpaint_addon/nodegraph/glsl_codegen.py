"""GLSL ES 3.00 from the graph description: the pipeline as one WebGL2 fragment shader (issue 17).

The fourth backend of pipeline_graph.describe, the web page's. Ordinary nodes are written by
text_codegen.py exactly as for OSL, with the same node helpers (shaders_osl/dp_nodes.h, read
through web/dp_words.glsl's #defines); here only the lookups (web/dp_tex.glsl) and the pseudo
nodes differ:

  dp.uv      the fragment's place in the painting's rectangle (`dp_rect`, framebuffer pixels)
  dp.sample  dp_tex on a sampler2D uniform `tex_<channel>` with explicit texel taps (no GPU
             filtering), `srgb_<channel>` saying whether it holds sRGB codes
  dp.param   a float uniform per parameter (text_codegen.param_name), set by the page
  dp.light   `light<n>_vector` (a sun's direction or a point light's position in the painting
             frame, §0) and `light<n>_weight` (k·c, §5), set by the page as the viewer drags
  dp.output  the premultiplied linear result; shown over the page's backdrop in sRGB, or kept
             as it is (`dp_display` 0) for a float framebuffer read back by the tests

The cos-θ term is always marched in the shader (shaders_osl/cos_theta.h, the OSL shader's
own march, §6): a page has no bake.
"""
import os

from .graph import FLOAT, VECTOR
from .text_codegen import Emitter, Program, indent, num, param_name, read_shared

WEB_DIR = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "web")
WRAPS = {"REPEAT": 0, "EXTEND": 1, "MIRROR": 2}
INTERPS = {"Linear": 0, "Closest": 1}


class GlslEmitter(Emitter):
    """The graph's nodes as GLSL statements and its pseudo nodes as uniforms and lookups."""
    VEC = "vec3"

    def op_dp_uv(self, n):
        self.define(n, 0, VECTOR, "dp_uv()")

    def op_dp_sample(self, n):
        channel = n.props["channel"]
        uv = self.ref(n.inputs["uv"], VECTOR) if "uv" in n.inputs else "dp_uv()"
        if channel.startswith("shadow_"):
            self.define(n, "color", VECTOR, "vec3({})".format(self.program.march_call(
                self.ref(n.inputs["normal"], VECTOR), self.ref(n.inputs["light"], VECTOR),
                n.props["kind"], uv)))
            self.bind(n, "alpha", FLOAT, "1.0")
            return
        tex, srgb = self.program.image(channel)
        self.lines.append(f"float n{n.id}_a;")
        self.define(n, "color", VECTOR, f"dp_tex({tex}, {srgb}, {uv}, "
                    f"{WRAPS[n.props['extension']]}, {INTERPS[n.props['interpolation']]}, n{n.id}_a)")
        self.bind(n, "alpha", FLOAT, f"n{n.id}_a")

    def op_dp_param(self, n):
        self.bind(n, 0, FLOAT, self.program.param(n.props["path"], n.props.get("index")))

    def op_dp_light(self, n):
        vector, weight = self.program.light(n.props["index"])
        self.bind(n, "vector", VECTOR, vector)
        self.bind(n, "weight", VECTOR, weight)

    def op_dp_output(self, n):
        self.lines.append(f"dp_show({self.ref(n.inputs['rgb'], VECTOR)}, "
                          f"{self.ref(n.inputs['alpha'])});")


class GlslProgram(Program):
    """The whole fragment shader: helpers, one function per sub-graph, uniforms, main."""
    OUT = "out"

    def __init__(self, features):
        super().__init__(features)
        self.uniforms = {}           # name → GLSL type
        self.textures = {}           # channel → sampler uniform

    def uniform(self, name, kind="float"):
        self.uniforms.setdefault(name, kind)
        return name

    def param(self, path, index=None):
        return self.uniform(param_name(path, index))

    def image(self, channel):
        """The sampler and sRGB flag uniforms of an image channel."""
        self.textures[channel] = self.uniform(f"tex_{channel}", "sampler2D")
        return self.textures[channel], self.uniform(f"srgb_{channel}", "int")

    def light(self, i):
        return (self.uniform(f"light{i + 1}_vector", "vec3"),
                self.uniform(f"light{i + 1}_weight", "vec3"))

    def march_call(self, normal, light, kind, uv):
        """The in-shader cos-θ term (shaders_osl/cos_theta.h) for one light."""
        f = self.features
        channel, along_ray, scale = self.march_relief()
        tex, srgb = self.image(channel)
        args = [normal, light, str(int(kind == "point")), f"{uv}.x", f"{uv}.y",
                tex, srgb, str(int(along_ray)),
                self.param("shape.flip_green"), self.param("shape.z_min"),
                num(f.size[0]), num(f.size[1]), scale, self.param("shadows.offset"),
                self.param("shadows.steps"), self.param("shadows.reach"),
                self.uniform("relief_max"), self.uniform("slope_max")]
        return f"dp_cos_theta({', '.join(args)})"


def generate(graph, features):
    """GLSL ES 3.00 fragment shader of the whole pipeline for `features`
    (graph = describe(features)) → (source, GlslProgram: its uniforms and textures)."""
    prog = GlslProgram(features)
    body = GlslEmitter(graph, prog).emit()
    functions = "\n".join(src for _, src in prog.functions.values())
    march_src = ""
    if features.shadows:
        march_src = prog.march_source()
    uniforms = "".join(f"uniform {kind} {name};\n" for name, kind in prog.uniforms.items())
    head = ("#version 300 es\n"
            "// Generated by dynpaint_addon/nodegraph/glsl_codegen.py from the pipeline's graph\n"
            "// description (pipeline.md §2–§11); do not edit: regenerate.\n"
            f"// Features: {features.key()}\n"
            "precision highp float;\nprecision highp int;\nprecision highp sampler2D;\n\n")
    return (head + read("dp_main.glsl") + uniforms + "\n" + read("dp_words.glsl")
            + read_shared("dp_nodes.h") + "\n" + read("dp_tex.glsl") + "\n" + functions + "\n"
            + march_src + "void main()\n{\n" + indent(body) + "}\n"), prog


def read(name):
    with open(os.path.join(WEB_DIR, name), encoding="utf-8") as fh:
        return fh.read()
