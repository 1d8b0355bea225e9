"""A painting in Blender as the web page's data (web/page.py, issue 17): its settings, its
lights and their animation, its frames (§16) — and a scene of layers whole (§15), its layers'
frames too (a lit Grease Pencil animation, issue 42). What File › Export › Dynamic Painting
(.html) and `export-web FILE.blend --grease-pencil` share."""
import dataclasses

from ...inputs.imageio import image_data_from_blender
from ...web.page import page_data, scene_data
from ..bake.layers import group_layers, group_materials, layer_parent
from ..state.frame_sampling import reading_lights
from ..state.frames import frame_data, moves, painting_frames, shown_frame, slot_frame
from ..state.lights import painting_lights
from ..state.settings import channel_images, settings_to_params

MAX_ANIMATION_FRAMES = 2000


def frame_rate(scene):
    return scene.render.fps / scene.render.fps_base


def played_frames(scene):
    """The scene frames the page plays: the scene's range, at most MAX_ANIMATION_FRAMES."""
    return range(scene.frame_start,
                 min(scene.frame_end, scene.frame_start + MAX_ANIMATION_FRAMES - 1) + 1)


def light_animation(mat, scene, progress=None):
    """The lights' vectors (painting frame) on every frame of the scene's range → {'fps',
    'frames'}, or None when no light moves. The frame is put back afterwards, the shadows as
    they were (nothing is baked for the frames visited)."""
    here = scene.frame_current
    played = played_frames(scene)
    frames = []
    with reading_lights():           # no shadow bakes for frames only visited to read them
        try:
            for n, frame in enumerate(played):
                scene.frame_set(frame)
                frames.append([list(lt.vector) for lt in painting_lights(mat, scene)])
                if progress:       # reading the lights is about a sixth of the export
                    progress(0.2 * (n + 1) / len(played))
        finally:
            scene.frame_set(here)
    if all(f == frames[0] for f in frames):
        return None
    return {"fps": frame_rate(scene), "frames": frames}


def group_frames(mats, scene):
    """A scene of layers whose layers move (§16) as scene_data's `frames`: the scene's range
    played, each distinct combination of the layers' frames read once → {'scenes', 'sequence',
    'fps'}; None when no layer moves."""
    if not any(moves(mat) for mat in mats):
        return None
    firsts, sequence = {}, []
    for f in played_frames(scene):
        key = tuple(shown_frame(mat, c, f) for mat in mats for c in channel_images(
            mat.dynamic_painting))
        sequence.append(firsts.setdefault(key, (len(firsts), f))[0])
    shown = [f for _, f in sorted(firsts.values())]
    first = group_layers(mats, f=shown[0])
    # a still image is read once: every drawing of the scene holds the same one
    return {"scenes": [first] + [[dataclasses.replace(layer, images={
        c: img if slot_frame(mat, c, f) is None else frame_data(mat, c, f)
        for c, img in layer.images.items()}) for mat, layer in zip(mats, first)]
        for f in shown[1:]], "sequence": sequence, "fps": frame_rate(scene)}


def painting_page(mat, scene, title, credits="", steps=None, max_size=None, animation=True,
                  progress=None):
    """The painting's web page data (web/page.py) → (data, warnings); a layer's: its whole
    scene of layers (§15), its layers' frames where they move."""
    parent = layer_parent(mat)
    mats = group_materials(parent) if parent is not None else [mat]
    anim = light_animation(mats[0], scene, progress) if animation else None
    if parent is not None:               # the lights in the back layer's frame, as the core's
        frames = group_frames(mats, scene)
        layers = frames["scenes"][0] if frames else group_layers(mats)
        return scene_data(layers, painting_lights(mats[0], scene), title=title,
                          credits=credits, steps=steps, max_size=max_size, frames=frames,
                          animation=anim)
    s = mat.dynamic_painting
    frames = None
    if moves(mat):                  # §16: every drawing of one loop, at the scene's rate
        painting = painting_frames(mat)
        frames = painting.web_frames(frame_rate(scene),
                                     lambda f: {c: frame_data(mat, c, f) for c in painting.slots})
        images = frames["drawings"][0]
    else:
        images = {c: image_data_from_blender(img) for c, img in channel_images(s).items()}
    return page_data(images, painting_lights(mat, scene), settings_to_params(s), title=title,
                     credits=credits, steps=steps, max_size=max_size, animation=anim,
                     frames=frames)
