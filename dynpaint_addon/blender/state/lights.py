"""The Blender lights that shade a painting, in the painting frame of docs/pipeline.md §0."""
import numpy as np

import bpy
from mathutils import Matrix, Vector

from ...core.lights import Light
from ..nodes.shader_backend import POINT_POWER_UNIT


def linked_lights(mat, scene):
    """The Sun and Point lights that shade this painting, in a stable order (by name)."""
    coll = mat.dynamic_painting.light_collection
    objects = coll.all_objects if coll is not None else scene.objects
    return sorted((o for o in objects if o.type == "LIGHT" and o.data.type in ("SUN", "POINT")),
                  key=lambda o: o.name)


def touched_by(depsgraph):
    """The original IDs a depsgraph update touched: objects moved or remade (a parent's move
    flags its children too; adding an object flags every other object's shading only, which
    no painting reads from them), lights' data, collections, scenes."""
    return {getattr(u.id, "original", u.id) for u in depsgraph.updates
            if not isinstance(u.id, bpy.types.Object) or u.is_updated_transform or
            u.is_updated_geometry}


def concerns(mat, scene, touched):
    """Could what `touched` holds change this painting's lights or plane? Its plane, its lights
    (their data, their parents: a turntable's pivot), its Lights collection; a painting lit by
    every light also by any light, collection or scene touched (a light added anywhere).
    Asked so that adding the 50th painting does not bring the other 49 up to date."""
    s = mat.dynamic_painting
    if s.light_collection is None and any(
            isinstance(t, (bpy.types.Collection, bpy.types.Scene, bpy.types.Light)) or
            (isinstance(t, bpy.types.Object) and t.type == "LIGHT") for t in touched):
        return True
    own = s.light_collection
    its = {mat} if own is None else {mat, own, *own.children_recursive}
    for obj in (s.plane, *linked_lights(mat, scene)):
        while obj is not None:
            its |= {obj, obj.data}
            obj = obj.parent
    return not its.isdisjoint(touched)


def painting_frame_light(obj, plane_matrix, depsgraph=None):
    """A Blender light → core Light in the painting frame (the plane's object space, §0).

    Uses the evaluated object when a depsgraph is given (animation renders, blender-notes.md).
    """
    ev = obj.evaluated_get(depsgraph) if depsgraph is not None else obj
    plane = np.array(plane_matrix, dtype=np.float64)
    inv = np.linalg.inv(plane)
    m = np.array(ev.matrix_world, dtype=np.float64)
    colour = tuple(ev.data.color)
    if ev.data.type == "SUN":       # its Angle softens the shadows layers cast (§15)
        direction = inv[:3, :3] @ (m[:3, :3] @ np.array([0.0, 0.0, 1.0]))
        return Light("sun", tuple(direction / np.linalg.norm(direction)), colour,
                     ev.data.energy, obj.name, size=ev.data.angle)
    pos = inv @ np.append(m[:3, 3], 1.0)
    radius = ev.data.shadow_soft_size / np.linalg.norm(plane[:3, 0])     # image widths
    return Light("point", tuple(pos[:3]), colour, ev.data.energy / POINT_POWER_UNIT, obj.name,
                 size=radius)


def plane_matrix(mat, depsgraph=None):
    """The world matrix of the painting's plane (evaluated when a depsgraph is given)."""
    plane = mat.dynamic_painting.plane
    if plane is None:
        raise ValueError("the painting has no plane")
    return (plane.evaluated_get(depsgraph) if depsgraph is not None else plane).matrix_world


def painting_lights(mat, scene, depsgraph=None):
    """The linked lights as core Lights in the painting frame (recipe export, compositor)."""
    m = plane_matrix(mat, depsgraph)
    return [painting_frame_light(o, m, depsgraph) for o in linked_lights(mat, scene)]


def aim(obj, rotation):
    """Turn `obj` to the quaternion `rotation` in its own rotation mode (a new object's is
    Euler XYZ, which scripts and drivers set: a Sun turned by quaternion ignored them)."""
    mode = obj.rotation_mode
    if mode == "QUATERNION":
        obj.rotation_quaternion = rotation
    elif mode == "AXIS_ANGLE":
        axis, angle = rotation.to_axis_angle()
        obj.rotation_axis_angle = (angle, *axis)
    else:
        obj.rotation_euler = rotation.to_euler(mode)


def add_light(scene, light, plane_matrix, collection):
    """Create a Blender light for a core Light given in the painting frame → the object."""
    kind = "SUN" if light.kind == "sun" else "POINT"
    data = bpy.data.lights.new(light.name or kind.title(), kind)
    data.color = light.colour
    data.energy = light.strength * (1.0 if kind == "SUN" else POINT_POWER_UNIT)
    m = Matrix(plane_matrix)
    if kind == "SUN":
        data.angle = light.size               # radians, as Blender's Sun Angle
    else:
        data.shadow_soft_size = light.size * m.to_scale()[0]      # image widths → scene units
    obj = bpy.data.objects.new(data.name, data)
    collection.objects.link(obj)
    if kind == "SUN":
        world_dir = (m.to_3x3() @ Vector(light.vector)).normalized()
        aim(obj, world_dir.to_track_quat("Z", "Y"))
        obj.location = m @ (Vector(light.vector).normalized() * 2.0)
    else:
        obj.location = m @ Vector(light.vector)
    return obj
