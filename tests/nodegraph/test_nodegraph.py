"""The graph description (nodegraph/, no bpy): pruning (§12), wiring, parameters."""
import dataclasses

import pytest

from dynpaint_addon import params
from dynpaint_addon.nodegraph.graph import Graph, Ref
from dynpaint_addon.nodegraph.pipeline_graph import Features, describe

MINIMAL = Features(size=(40, 30))
FULL = Features(size=(40, 30), channels=frozenset(params.CHANNELS), lights=("sun", "point"),
                shadows=True, specular=True, transparency="map", silhouette="shape",
                lookup_sizes=(("background", (48, 40)), ("environment", (32, 24))))


def test_a_node_may_read_only_nodes_made_before_it():
    """Graph.add keeps every graph topological (issue 28, point 7: the old check of the built
    graphs could not fail, since add made it so): a forward or dangling reference is refused."""
    g = Graph("g")
    a = g.add("dp.value", value=1.0)
    g.add("math", {"a": Ref(a.id)})
    for bad in (Ref(a.id + 2), Ref(-1)):
        with pytest.raises(ValueError, match="does not come before it"):
            g.add("math", {"a": bad})
    assert len(g.nodes) == 2


def test_parameters_exist_in_params_table():
    used = describe(FULL).params() | describe(dataclasses.replace(
        FULL, refraction_mode="linear", fresnel_mode="art")).params()
    assert used <= set(params.BY_PATH)
    assert {"diffuse.t0", "diffuse.t1", "refraction.ior", "reflection.distance"} <= used


def test_minimal_tree_has_only_what_the_scene_needs():
    ops = describe(MINIMAL).ops()
    names = " ".join(o for o in ops if o.startswith("group:"))
    for absent in ("Reflection", "Refraction", "Fresnel", "Height", "shadowed", "specular"):
        assert absent not in names
    assert describe(MINIMAL).channels() == {"shape", "dark", "bright"}
    assert MINIMAL.image_channels() == {"shape", "dark", "bright"}


def test_each_feature_adds_its_branch():
    base = describe(MINIMAL).count()
    for change, marker in [({"specular": True}, "specular"),
                           ({"shadows": True}, "shadowed"),
                           ({"shape_kind": "height"}, "Height Gradient"),
                           ({"lights": ("sun", "point")}, "Light point")]:
        g = describe(dataclasses.replace(MINIMAL, **change))
        assert g.count() > base, change
        assert any(marker in o for o in g.ops()), change


def test_the_image_size_is_a_value_not_the_structure():
    """Two sizes of the same painting: the same nodes and links, node for node (their
    nodes_key equal), the size a pseudo node's value (dp.size) — so a painting framed anew
    keeps its tree (issue 61: the rebuild held Blender 20–30 ms a layer)."""
    def shape(g):
        return [(n.op, {k: getattr(v, "name", v) for k, v in n.props.items()}, n.inputs)
                for n in g.nodes]
    for f in (FULL, dataclasses.replace(FULL, shape_kind="height")):
        other = dataclasses.replace(f, size=(97, 61))
        assert f.nodes_key() == other.nodes_key() and f.key() != other.key()
        assert shape(describe(f)) == shape(describe(other))
        assert "dp.size" in describe(f).ops()


def test_channels_sampled_are_the_channels_required():
    for f in (MINIMAL, FULL, dataclasses.replace(FULL, shape_kind="height", silhouette="dark")):
        assert describe(f).channels() == f.image_channels()


def test_one_light_group_per_light_and_shared_node_groups():
    g = describe(dataclasses.replace(MINIMAL, lights=("sun", "sun", "point")))
    light_nodes = [n for n in g.nodes if n.op == "dp.light"]
    assert [n.props["kind"] for n in light_nodes] == ["sun", "sun", "point"]
    groups = [n.props["graph"] for n in g.nodes if n.op == "dp.group"
              and n.props["graph"].name.startswith("DP Light sun")]
    assert len(groups) == 2 and groups[0] is groups[1]    # one node group, used twice


@pytest.mark.parametrize("amount, has_map, expected", [
    ("auto", False, "none"), ("auto", True, "map"), (0.0, False, "none"), (0.5, False, "param"),
    (0.0, True, "param")])
def test_transparency_branch_resolution(amount, has_map, expected):
    p = params.defaults()
    p.transparency.amount = amount
    channels = {"shape", "dark"} | ({"transparency"} if has_map else set())
    assert Features.from_params(p, channels, ["sun"], (4, 4)).transparency == expected


def test_live_values_do_not_change_structure():
    p = params.defaults()
    a = Features.from_params(p, {"shape", "dark"}, ["sun"], (4, 4))
    p.diffuse.t0, p.refraction.ior, p.shape.height_scale = 0.3, 1.9, 0.5
    assert Features.from_params(p, {"shape", "dark"}, ["sun"], (4, 4)) == a
    p.specular.enabled = True
    assert Features.from_params(p, {"shape", "dark"}, ["sun"], (4, 4)) != a
