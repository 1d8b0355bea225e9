"""A painting's node tree: built from the graph description for its features, and rebuilt
exactly when they change (docs/pipeline.md §12). Values (t0, η, …) reach the tree through
drivers (nodes/shader_backend.py), so changing one rebuilds nothing."""
from . import osl
from ...nodegraph.pipeline_graph import describe
from ..nodes import build
from ..nodes.shader_backend import ShaderBackend, set_image_size
from ..state.painting_state import read_state


def signature(features, lights, images):
    """What the tree's nodes and links are built from — features but the values set in place
    (the image size), lights, the images its nodes sample: equal signatures, equal trees."""
    sampled = sorted((c, images[c].name) for c in features.image_channels() if c in images)
    return repr((features.nodes_key(), [o.name for o in lights], sampled))


def sync_light_items(s, lights):
    """Keep s.lights in the order of `lights`, each with its shadow image."""
    if [(i.object, i.kind) for i in s.lights] == [(o, o.data.type) for o in lights]:
        return
    old = {item.object.name: (item.shadow, item.bake_key) for item in s.lights
           if item.object is not None}
    s.lights.clear()
    for obj in lights:
        item = s.lights.add()
        item.object = obj
        item.kind = obj.data.type
        item.shadow, item.bake_key = old.get(obj.name, (None, ""))


def tree_images(s, inputs):
    """{channel: image} the tree samples: the inputs ({channel: image}), the derived images
    replacing or adding to them, and one cos-θ image per light ('shadow_<i>')."""
    images = dict(inputs)
    images.update({item.channel: item.image for item in s.derived})
    images.update({f"shadow_{i}": item.shadow for i, item in enumerate(s.lights)
                   if item.shadow is not None})
    return images


def rebuild_tree(mat, scene, force=False, state=None):
    """Rebuild the node tree if its features or lights changed (or `force`), else set its image
    size in place (a painting framed anew: 20–30 ms of rebuild saved). → True if rebuilt.
    state: the PaintingState of this update (read now if not given)."""
    s = mat.dynamic_painting
    state = state or read_state(mat, scene)
    f, lights = state.features, state.lights
    sync_light_items(s, lights)
    images = tree_images(s, state.images)
    sig = signature(f, lights, images)
    if f.shadow_source == "osl" and state.frame:
        # the OSL shader reads its images from files: a moving painting's drawing is written
        # to files of its own (§16), read by a shader set up for them
        sig += repr(state.frame)
    if f.shadow_source == "osl":
        sig += repr(f.size)           # (the shader's text is written for one size)
    if not force and sig == s.signature and len(mat.node_tree.nodes) and \
            set_image_size(mat.node_tree, f.size):
        return False
    missing = f.image_channels() - images.keys()
    if missing:
        raise ValueError(f"images not ready: {', '.join(sorted(missing))}")
    tree = mat.node_tree
    tree.animation_data_clear()
    tree.nodes.clear()
    build.build(tree, describe(f), ShaderBackend(mat, images, lights, f.size))
    if f.shadow_source == "osl":
        # Cycles renders the OSL shader (in-shader march); EEVEE keeps the node material.
        eevee_out = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial")
        eevee_out.target = "EEVEE"
        osl.build_osl_tree(mat, f, images, lights, march=f.shadows, p=state.params,
                           tag="".join(f" {c}{n}" for c, n in state.frame))
        cycles_out = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial"
                          and n != eevee_out)
        cycles_out.target = "CYCLES"
        scene.cycles.shading_system = True
    may_be_transparent = f.has_lookups or bool(f.silhouette)
    mat.surface_render_method = "BLENDED" if may_be_transparent else "DITHERED"
    s.signature = sig
    return True


def tree_is_stale(mat):
    """An image the node tree samples was deleted (its node lost the image)."""
    return any(n.bl_idname == "ShaderNodeTexImage" and n.image is None
               for n in mat.node_tree.nodes)
