"""OSL source from the graph description: the pipeline as one Cycles Script node (issue 5).

The third backend of pipeline_graph.describe, and a textual one: every node becomes an OSL
statement with Blender's own node semantics (division by zero gives 0, Map Range at
From Min = From Max gives To Min, …), every sub-graph an OSL function, image lookups
`texture()` calls on files, parameters and lights shader parameters (the add-on drives them
like the material's sockets). The cos-θ term can come from a baked image or from the march in
`shaders_osl/cos_theta.h`, evaluated per shading point (no bake).

No bpy here: the text can be generated and inspected anywhere.
"""
import os

from .graph import FLOAT, VECTOR, Ref

HERE = os.path.dirname(os.path.abspath(__file__))
OSL_DIR = os.path.join(os.path.dirname(os.path.dirname(HERE)), "shaders_osl")
WRAPS = {"REPEAT": "periodic", "EXTEND": "clamp", "MIRROR": "mirror"}
INTERPS = {"Linear": "linear", "Closest": "closest"}

MATH = {
    "ADD": "({0} + {1})", "SUBTRACT": "({0} - {1})", "MULTIPLY": "({0} * {1})",
    "DIVIDE": "dp_div({0}, {1})", "MULTIPLY_ADD": "({0} * {1} + {2})", "POWER": "dp_pow({0}, {1})",
    "SQRT": "dp_sqrt({0})", "ABSOLUTE": "fabs({0})", "SIGN": "dp_sign({0})",
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


def _literal(value):
    if isinstance(value, (tuple, list)):
        return "vector({})".format(", ".join(_num(v) for v in value[:3]))
    return _num(value)


def _num(v):
    text = repr(float(v))
    return text if ("e" in text or "." in text or "inf" in text) else text + ".0"


def ident(text):
    """An OSL identifier: 'DP Light sun (§4–§7)' → 'DP_Light_sun_4_7'."""
    out = "".join(c if c.isascii() and c.isalnum() else "_" for c in text)
    return "_".join(part for part in out.split("_") if part)


def param_name(path, index=None):
    """The shader parameter of a params.py parameter, or of its component `index`:
    'diffuse.t0' → 'p_diffuse_t0', ('reflection.offset', 1) → 'p_reflection_offset_y'."""
    return "p_" + ident(path) + ("" if index is None else "_" + "xy"[index])


class Emitter:
    """Turns one Graph's nodes into OSL statements (a function body or the shader body)."""

    def __init__(self, graph, program):
        self.graph = graph
        self.program = program
        self.lines = []
        self.values = {}         # (node id, output) → OSL expression (a variable name)
        self.types = {}

    def ref(self, value, want=FLOAT):
        if isinstance(value, Ref):
            expr = self.values[(value.node, value.output)]
            kind = self.types[(value.node, value.output)]
            if want == VECTOR and kind == FLOAT:
                return f"vector({expr})"
            return expr
        if want == VECTOR and not isinstance(value, (tuple, list)):
            return f"vector({_num(value)})"
        return _literal(value)

    def define(self, node, output, kind, expr):
        name = f"n{node.id}_{ident(str(output))}" if output not in (0, "0") else f"n{node.id}"
        ctype = "float" if kind == FLOAT else "vector"
        self.lines.append(f"{ctype} {name} = {expr};")
        self.values[(node.id, output)] = name
        self.types[(node.id, output)] = kind

    def emit(self):
        for n in self.graph.nodes:
            getattr(self, "op_" + ident(n.op))(n)
        return self.lines

    # -- ordinary nodes -----------------------------------------------------------------
    def op_ShaderNodeMath(self, n):
        args = [self.ref(n.inputs.get(i, 0.0)) for i in range(3)]
        expr = MATH[n.props["operation"]].format(*args)
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
        self.define(n, 0, VECTOR, "vector({}, {}, {})".format(
            *[self.ref(n.inputs.get(i, 0.0)) for i in range(3)]))

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
                        f"dp_vmix({a}, {b}, clamp({f}, vector(0.0), vector(1.0)))")

    # -- structure ----------------------------------------------------------------------
    def op_dp_group_input(self, n):
        for name, kind in self.graph.inputs:
            self.values[(n.id, name)] = ident(name)
            self.types[(n.id, name)] = kind

    def op_dp_group_output(self, n):
        for name, kind in self.graph.outputs:
            self.lines.append(f"out_{ident(name)} = {self.ref(n.inputs[name], kind)};")

    def op_dp_group(self, n):
        sub = n.props["graph"]
        fn = self.program.function(sub)
        args = [self.ref(n.inputs.get(name, 0.0), kind) for name, kind in sub.inputs]
        outs = []
        for name, kind in sub.outputs:
            var = f"n{n.id}_{ident(name)}"
            self.lines.append(f"{'float' if kind == FLOAT else 'vector'} {var};")
            self.values[(n.id, name)] = var
            self.types[(n.id, name)] = kind
            outs.append(var)
        self.lines.append(f"{fn}({', '.join(args + outs)});")

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
        param = self.program.image(channel)
        self.lines.append(f"float n{n.id}_a;")
        self.define(n, "color", VECTOR,
                    f'dp_tex({param}_file, {param}_srgb, {uv}, "{WRAPS[n.props["extension"]]}", '
                    f'"{INTERPS[n.props["interpolation"]]}", n{n.id}_a)')
        self.values[(n.id, "alpha")] = f"n{n.id}_a"
        self.types[(n.id, "alpha")] = FLOAT

    def op_dp_param(self, n):
        self.values[(n.id, 0)] = self.program.param(n.props["path"], n.props.get("index"))
        self.types[(n.id, 0)] = FLOAT

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


class Program:
    """The whole shader: helpers, one function per sub-graph, parameters, body."""

    def __init__(self, features, march=False):
        self.features = features
        self.march = march
        self.functions = {}          # sub-graph name → (function name, source)
        self.params = {}             # declaration lines, by name

    def function(self, sub):
        if sub.name not in self.functions:
            name = ident(sub.name)
            body = Emitter(sub, self).emit()
            args = [f"{'float' if k == FLOAT else 'vector'} {ident(n)}" for n, k in sub.inputs]
            args += [f"output {'float' if k == FLOAT else 'vector'} out_{ident(n)}"
                     for n, k in sub.outputs]
            src = f"void {name}({', '.join(args)})\n{{\n" + _indent(body) + "}\n"
            self.functions[sub.name] = (name, src)
        return self.functions[sub.name][0]

    def param(self, path, index=None):
        name = param_name(path, index)
        self.params.setdefault(name, f"float {name} = 0.0")
        return name

    def image(self, channel):
        name = ident(channel)
        self.params.setdefault(name + "_file", f'string {name}_file = ""')
        self.params.setdefault(name + "_srgb", f"int {name}_srgb = 0")
        return name

    def march_call(self, normal, light, kind, uv):
        """The in-shader cos-θ term (shaders_osl/cos_theta.h) for one light."""
        f = self.features
        along_ray = f.shape_kind == "normal" and not f.marches_relief    # slopes, else heights
        relief = self.image("relief" if f.marches_relief else "shape" if along_ray else "height")
        args = [normal, light, str(int(kind == "point")), f"{uv}[0]", f"{uv}[1]",
                f"{relief}_file", f"{relief}_srgb", str(int(along_ray)),
                self.param("shape.flip_green"), self.param("shape.z_min"),
                _num(f.size[0]), _num(f.size[1]),
                "1.0" if f.marches_relief else self.param("shape.height_scale"),   # widths
                self.param("shadows.offset"), self.param("shadows.steps"),
                self.param("shadows.reach"), "relief_max",
                "slope_max"]
        self.params.setdefault("relief_max", "float relief_max = 0.0")
        self.params.setdefault("slope_max", "float slope_max = 0.0")
        return f"dp_cos_theta({', '.join(args)})"

    def light(self, i, kind):
        n = i + 1
        self.params.setdefault(f"light{n}_world", f"vector light{n}_world = vector(0.0, 0.0, 1.0)")
        self.params.setdefault(f"light{n}_color", f"color light{n}_color = color(1.0)")
        self.params.setdefault(f"light{n}_strength", f"float light{n}_strength = 1.0")


def _indent(lines):
    return "".join(f"    {ln}\n" for ln in lines)


def generate(graph, features, march=False, name="dynamic_painting"):
    """OSL source of the whole pipeline for `features` (graph = describe(features)).

    march: compute the cos-θ term in the shader (shaders_osl/cos_theta.h) instead of
    reading baked images.
    """
    prog = Program(features, march)
    body = Emitter(graph, prog).emit()
    params = ["vector painting_uv = vector(0.0)"] + list(prog.params.values()) + [
        "output color Color = 0", "output float Alpha = 1", "output color Pass_W = 0",
        "output color Pass_s = 0", "output float Pass_F = 0"]
    functions = "\n".join(src for _, src in prog.functions.values())
    march_src = ""
    if march and features.shadows:
        decode = next((fn for key, (fn, _) in prog.functions.items()
                       if key.startswith("DP Normal Map")), None)
        macro = (f"#define DP_NORMAL_DECODE(c, flip, zmin, n) {decode}(c, flip, zmin, n)\n"
                 if decode else "#define DP_NORMAL_DECODE(c, flip, zmin, n) n = vector(0, 0, 1)\n")
        march_src = macro + _read("cos_theta.h") + "\n"
    head = ("// Generated by dynpaint_addon/nodegraph/osl_codegen.py from the pipeline's graph\n"
            "// description (pipeline.md §2–§11); do not edit: regenerate.\n"
            f"// Features: {features.key()}\n#include \"stdosl.h\"\n\n")
    return (head + _read("dp_nodes.h") + "\n" + functions + "\n" + march_src
            + f"shader {name}(\n" + ",\n".join("    " + p for p in params) + ")\n{\n"
            + _indent(body) + "}\n")


def _read(name):
    with open(os.path.join(OSL_DIR, name), encoding="utf-8") as fh:
        return fh.read()
