"""The textual backends (OSL, GLSL) generated from the one graph description (no bpy, no
browser): what they declare is derived from the graph, and both languages define the same
node semantics. Their pixels are checked in tests/blender/test_osl.py (Cycles) and
tests/blender/test_web_page.py (a real browser)."""
import dataclasses
import re

import pytest

from dynpaint_addon import params
from dynpaint_addon.nodegraph import glsl_codegen, osl_codegen
from dynpaint_addon.nodegraph.pipeline_graph import Features, describe
from dynpaint_addon.nodegraph.text_codegen import param_name
from dynpaint_addon.web.page import param_uniforms

FULL = Features(size=(40, 30), channels=frozenset(params.CHANNELS), lights=("sun", "point"),
                shadows=True, specular=True, transparency="map", silhouette="shape",
                shadow_source="osl",
                lookup_sizes=(("background", (48, 40)), ("environment", (32, 24))))
CASES = {"minimal": Features(size=(40, 30)), "full": FULL,
         "height": dataclasses.replace(FULL, shape_kind="height"),
         "relief": dataclasses.replace(FULL, shadows_relief="integrated", silhouette="")}


def helpers(text):
    return set(re.findall(r"^\w+\s+(dp_\w+)\s*\(", text, re.M))


def test_both_languages_define_the_same_node_helpers():
    osl = helpers(osl_codegen._read("dp_nodes.h"))
    glsl = helpers(glsl_codegen.read("dp_nodes.glsl"))
    assert {"dp_div", "dp_pow", "dp_map_range", "dp_abs", "dp_tex"} <= osl
    assert osl <= glsl, f"missing in GLSL: {osl - glsl}"
    assert helpers(osl_codegen._read("cos_theta.h")) == helpers(glsl_codegen.read("cos_theta.glsl"))


@pytest.mark.parametrize("case", CASES)
def test_glsl_declares_what_the_graph_reads(case):
    f = CASES[case]
    graph = describe(f)
    src, prog = glsl_codegen.generate(graph, f)
    assert src.startswith("#version 300 es\n") and "void main()" in src
    declared = set(re.findall(r"^uniform \w+ (\w+);", src, re.M))
    assert declared == set(prog.uniforms) | {"dp_rect", "dp_display", "dp_backdrop"}
    # every parameter the graph reads is a uniform the page sets from params.py
    for path in graph.params():
        assert param_name(path) in declared or param_name(path, 0) in declared
    assert {u for u in declared if u.startswith("p_")} <= set(param_uniforms(params.defaults()))
    # every image the graph samples is a sampler, except the cos-θ terms: marched in the page
    wanted = {c for c in f.image_channels() if not c.startswith("shadow_")}
    assert {u[4:] for u in declared if u.startswith("tex_")} == wanted
    assert ("dp_cos_theta(" in src) == bool(f.shadows and f.lights)
    assert all(f"light{i + 1}_vector" in declared for i in range(len(f.lights)))


def test_osl_and_glsl_are_one_body_in_two_languages():
    """Same statements node for node: only the words and the pseudo nodes differ."""
    f = FULL
    osl = osl_codegen.generate(describe(f), f, march=True)
    glsl, _ = glsl_codegen.generate(describe(f), f)

    def calls(text):
        return sorted(re.findall(r"\b(DP_\w+)\(", text))
    assert calls(osl) == calls(glsl)
    generated = glsl.split("// Features")[1]
    assert "vector(" not in generated and "output " not in generated
