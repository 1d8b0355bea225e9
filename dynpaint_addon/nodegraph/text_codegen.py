"""Source text from the graph description: what the OSL and GLSL backends share (issues 5, 17).

Both shading languages are C-like, so every ordinary node (Math, Vector Math, Map Range, Mix,
Separate/Combine XYZ) becomes the same statement in both, with Blender's node semantics
kept by small helper functions named `dp_…` (division by zero gives 0, Map Range at
From Min = From Max gives To Min, …). Those helpers and the in-shader cos-θ march are written
once for both languages (snippets/shared/dp_nodes.h, snippets/shared/cos_theta.h); GLSL
reads them through a prelude of #defines (snippets/glsl/dp_words.glsl). Every sub-graph
becomes a function with output parameters. A language differs in two words (its vector type,
its output qualifier), in its image lookups (snippets/osl/dp_tex.h, snippets/glsl/dp_tex.glsl)
and in the backend-specific pseudo nodes (dp.uv, dp.sample, dp.param, dp.light, dp.output),
which each backend's Emitter subclass writes. The hand-written snippets sit in one folder per
language beside this generator (snippets/README.md), as MaterialX keeps its genosl/genglsl.

No bpy here: the text can be generated and inspected anywhere.
"""
import os

from .graph import FLOAT, VECTOR, Ref

# The hand-written shader sources: snippets/shared (both languages), snippets/osl, snippets/glsl.
SNIPPETS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "snippets")

MATH = {
    "ADD": "({0} + {1})", "SUBTRACT": "({0} - {1})", "MULTIPLY": "({0} * {1})",
    "DIVIDE": "dp_div({0}, {1})", "MULTIPLY_ADD": "({0} * {1} + {2})", "POWER": "dp_pow({0}, {1})",
    "SQRT": "dp_sqrt({0})", "ABSOLUTE": "dp_abs({0})", "SIGN": "dp_sign({0})",
    "MINIMUM": "min({0}, {1})", "MAXIMUM": "max({0}, {1})", "LESS_THAN": "({0} < {1} ? 1.0 : 0.0)",
    "GREATER_THAN": "({0} > {1} ? 1.0 : 0.0)", "COMPARE": "dp_compare({0}, {1}, {2})",
    "FLOOR": "floor({0})",
}
VMATH = {
    "ADD": "({0} + {1})", "SUBTRACT": "({0} - {1})", "MULTIPLY": "({0} * {1})",
    "DIVIDE": "dp_vdiv({0}, {1})", "MULTIPLY_ADD": "({0} * {1} + {2})", "SCALE": "({0} * {3})",
    "NORMALIZE": "dp_normalize({0})", "LENGTH": "length({0})", "DOT_PRODUCT": "dot({0}, {1})",
    "MINIMUM": "min({0}, {1})", "MAXIMUM": "max({0}, {1})",
}
MAP_RANGE = {"LINEAR": 0, "SMOOTHSTEP": 1, "SMOOTHERSTEP": 2}


def num(v):
    """A float literal both languages read: 1 → '1.0'."""
    text = repr(float(v))
    return text if ("e" in text or "." in text or "inf" in text) else text + ".0"


def ident(text):
    """An identifier: 'DP Light sun (§4–§7)' → 'DP_Light_sun_4_7'."""
    out = "".join(c if c.isascii() and c.isalnum() else "_" for c in text)
    return "_".join(part for part in out.split("_") if part)


def param_name(path, index=None):
    """The shader parameter (OSL) or uniform (GLSL) of a params.py parameter, or of its
    component `index`: 'diffuse.t0' → 'p_diffuse_t0', ('reflection.offset', 1) →
    'p_reflection_offset_y'."""
    return "p_" + ident(path) + ("" if index is None else "_" + "xy"[index])


def read_snippet(language, name):
    """The text of a hand-written shader source: `language` is "shared" (written in the words
    both languages read), "osl" or "glsl"; e.g. ("shared", "cos_theta.h")."""
    with open(os.path.join(SNIPPETS, language, name), encoding="utf-8") as fh:
        return fh.read()


def indent(lines):
    return "".join(f"    {ln}\n" for ln in lines)


class Emitter:
    """Turns one Graph's nodes into statements (a function body or the main body).

    A subclass names its language's words and writes the pseudo nodes (op_dp_uv, op_dp_sample,
    op_dp_param, op_dp_light, op_dp_output); op_dp_size is the same in every language."""
    VEC = "vector"          # the 3-vector type, also its constructor

    def __init__(self, graph, program):
        self.graph = graph
        self.program = program
        self.lines = []
        self.values = {}         # (node id, output) → expression (a variable name)
        self.types = {}

    def vec(self, *parts):
        return f"{self.VEC}({', '.join(parts)})"

    def type_name(self, kind):
        return "float" if kind == FLOAT else self.VEC

    def literal(self, value, want=FLOAT):
        if isinstance(value, (tuple, list)):
            return self.vec(*(num(v) for v in value[:3]))
        return self.vec(num(value)) if want == VECTOR else num(value)

    def ref(self, value, want=FLOAT):
        if isinstance(value, Ref):
            expr = self.values[(value.node, value.output)]
            kind = self.types[(value.node, value.output)]
            return self.vec(expr) if want == VECTOR and kind == FLOAT else expr
        return self.literal(value, want)

    def define(self, node, output, kind, expr):
        name = f"n{node.id}_{ident(str(output))}" if output not in (0, "0") else f"n{node.id}"
        self.lines.append(f"{self.type_name(kind)} {name} = {expr};")
        self.bind(node, output, kind, name)

    def bind(self, node, output, kind, expr):
        """Output `output` of `node` is `expr` (no statement)."""
        self.values[(node.id, output)] = expr
        self.types[(node.id, output)] = kind

    def emit(self):
        for n in self.graph.nodes:
            getattr(self, "op_" + ident(n.op))(n)
        return self.lines

    # -- ordinary nodes -----------------------------------------------------------------
    def positive(self, value):
        """Whether a float input is > 0 by construction (a positive constant, the maximum with
        one, sums, products and quotients of such): Blender's guards for zero and negative
        operands are then not needed."""
        if not isinstance(value, Ref):
            return isinstance(value, (int, float)) and value > 0
        node = self.graph.nodes[value.node]
        if node.op == "dp.size":
            return True
        if node.op != "ShaderNodeMath":
            return False
        op, a, b = node.props["operation"], node.inputs.get(0, 0.0), node.inputs.get(1, 0.0)
        if op == "MAXIMUM":
            return self.positive(a) or self.positive(b)
        if op in ("ADD", "MULTIPLY", "DIVIDE"):
            return self.positive(a) and self.positive(b)
        return False

    def op_ShaderNodeMath(self, n):
        args = [self.ref(n.inputs.get(i, 0.0)) for i in range(3)]
        op = n.props["operation"]
        if op == "DIVIDE" and self.positive(n.inputs.get(1, 0.0)):
            expr = f"({args[0]} / {args[1]})"          # no division by zero to guard
        elif op == "POWER" and self.positive(n.inputs.get(0, 0.0)):
            expr = f"pow({args[0]}, {args[1]})"        # a positive base: the plain power
        else:
            expr = MATH[op].format(*args)
        if n.props.get("use_clamp"):
            expr = f"clamp({expr}, 0.0, 1.0)"
        self.define(n, 0, FLOAT, expr)

    def op_ShaderNodeVectorMath(self, n):
        op = n.props["operation"]
        args = [self.ref(n.inputs.get(i, (0.0, 0.0, 0.0)), VECTOR) for i in range(3)]
        args.append(self.ref(n.inputs.get(3, 1.0)))
        expr = VMATH[op].format(*args)
        out = 1 if op in ("LENGTH", "DOT_PRODUCT") else 0
        self.define(n, out, FLOAT if out else VECTOR, expr)

    def op_ShaderNodeSeparateXYZ(self, n):
        v = self.ref(n.inputs[0], VECTOR)
        for i in range(3):
            self.define(n, i, FLOAT, f"{v}[{i}]")

    def op_ShaderNodeCombineXYZ(self, n):
        self.define(n, 0, VECTOR, self.vec(*[self.ref(n.inputs.get(i, 0.0)) for i in range(3)]))

    def op_ShaderNodeMapRange(self, n):
        i = n.inputs
        args = ", ".join(self.ref(i[k]) for k in ("Value", "From Min", "From Max", "To Min",
                                                     "To Max"))
        self.define(n, "Result", FLOAT, f"dp_map_range({args}, "
                    f"{MAP_RANGE[n.props['interpolation_type']]}, {int(n.props['clamp'])})")

    def op_ShaderNodeMix(self, n):
        if n.props["data_type"] == "FLOAT":
            f, a, b = (self.ref(n.inputs[k]) for k in ("Factor_Float", "A_Float", "B_Float"))
            self.define(n, "Result_Float", FLOAT, f"dp_mix({a}, {b}, clamp({f}, 0.0, 1.0))")
        else:
            f, a, b = (self.ref(n.inputs[k], VECTOR) for k in ("Factor_Vector", "A_Vector",
                                                                  "B_Vector"))
            self.define(n, "Result_Vector", VECTOR,
                        f"dp_vmix({a}, {b}, clamp({f}, {self.vec('0.0')}, {self.vec('1.0')}))")

    # -- structure ----------------------------------------------------------------------
    def op_dp_size(self, n):
        """The image size as numbers: a shader's text is written for one size."""
        for output, value in zip(("width", "height"), self.program.features.size):
            self.bind(n, output, FLOAT, num(float(value)))

    def op_dp_group_input(self, n):
        for name, kind in self.graph.inputs:
            self.bind(n, name, kind, ident(name))

    def op_dp_group_output(self, n):
        for name, kind in self.graph.outputs:
            self.lines.append(f"out_{ident(name)} = {self.ref(n.inputs[name], kind)};")

    def op_dp_group(self, n):
        sub = n.props["graph"]
        fn = self.program.function(sub, type(self))
        args = [self.ref(n.inputs.get(name, 0.0), kind) for name, kind in sub.inputs]
        outs = []
        for name, kind in sub.outputs:
            var = f"n{n.id}_{ident(name)}"
            self.lines.append(f"{self.type_name(kind)} {var};")
            self.bind(n, name, kind, var)
            outs.append(var)
        self.lines.append(f"{fn}({', '.join(args + outs)});")


class Program:
    """The functions of the sub-graphs (each written once, inner ones first) and the
    parameters a backend declares, by name."""
    OUT = "output"          # the output-parameter qualifier

    def __init__(self, features):
        self.features = features
        self.functions = {}          # sub-graph name → (function name, source)
        self.params = {}             # declaration, by name

    def function(self, sub, emitter):
        if sub.name not in self.functions:
            name = ident(sub.name)
            em = emitter(sub, self)
            body = em.emit()
            args = [f"{em.type_name(k)} {ident(n)}" for n, k in sub.inputs]
            args += [f"{self.OUT} {em.type_name(k)} out_{ident(n)}" for n, k in sub.outputs]
            src = f"void {name}({', '.join(args)})\n{{\n" + indent(body) + "}\n"
            self.functions[sub.name] = (name, src)
        return self.functions[sub.name][0]

    def march_source(self):
        """The shared in-shader march (snippets/shared/cos_theta.h), after the graph's functions,
        with the graph's §2 normal decode as its DP_NORMAL_DECODE (a height map's march never
        decodes one)."""
        decode = next((fn for key, (fn, _) in self.functions.items()
                       if key.startswith("DP Normal Map")), None)
        macro = f"{decode}(c, flip, zmin, n)" if decode else "n = vector(0, 0, 1)"
        return (f"#define DP_NORMAL_DECODE(c, flip, zmin, n) {macro}\n"
                + read_snippet("shared", "cos_theta.h") + "\n")

    def march_call(self, normal, light, kind, uv):
        """The in-shader cos-θ term of one light (snippets/shared/cos_theta.h), in either
        language. It marches a normal map's integrated relief (§6 "Relief", image widths),
        the normal map itself rebuilt along the ray from its slopes, or the pre-blurred
        height map; a backend names the image's arguments (image_arguments) and the march's
        global bounds (bound)."""
        f = self.features
        along_ray = f.shape_kind == "normal" and not f.marches_relief
        channel = "relief" if f.marches_relief else "shape" if along_ray else "height"
        scale = "1.0" if f.marches_relief else self.param("shape.height_scale")
        args = [normal, light, str(int(kind == "point")), f"{uv}[0]", f"{uv}[1]",
                *self.image_arguments(channel), str(int(along_ray)),
                self.param("shape.flip_green"), self.param("shape.z_min"),
                num(f.size[0]), num(f.size[1]), scale, self.param("shadows.offset"),
                self.param("shadows.steps"), self.param("shadows.reach"),
                self.bound("relief_max"), self.bound("slope_max"), self.bound("reach_limited")]
        return f"dp_cos_theta({', '.join(args)})"
