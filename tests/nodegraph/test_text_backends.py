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
from dynpaint_addon.nodegraph.text_codegen import param_name, read_snippet
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


def test_shared_shader_sources_use_only_words_both_languages_read():
    """dp_nodes.h and cos_theta.h are written once for OSL and GLSL: no word of one language
    only (GLSL's prelude #defines `vector`, `fabs`, `output`, DP_IMAGE), no C cast, no int
    used as a truth value; both generated shaders hold them verbatim."""
    f = FULL
    osl = osl_codegen.generate(describe(f), f, march=True)
    glsl, _ = glsl_codegen.generate(describe(f), f)
    for name in ("dp_nodes.h", "cos_theta.h"):
        text = read_snippet("shared", name)
        code = re.sub(r"//.*", "", text)
        for word in ("vec2", "vec3", "texture(", "string", "color", "bool", "true", "false",
                     "const ", "(int)", "(float)", "point("):
            assert word not in code, (name, word)
        assert not re.search(r"if \((!?)(is_point|normal_map|stopped|by_reach|clamp_)\)", code)
        assert text in osl and text in glsl
    # each language's lookups: the image at a UV, and the march's (linear, edges extended)
    both = helpers(read_snippet("osl", "dp_tex.h")) & helpers(read_snippet("glsl", "dp_tex.glsl"))
    assert {"dp_tex", "dp_image_at"} <= both


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
    body = glsl.split("void main()")[1]
    assert "vector(" not in body and "output " not in body
