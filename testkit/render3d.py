"""Ground truth from 3D, as the benchmarks and sample generators render it with Cycles: emission
materials that show a quantity (height, normal, index) as colour, and an orthographic camera
looking down −Z (the painting frame's view, §0)."""


def emission_material(name, build):
    """A material that emits build(node_tree) → the output socket to show, as is."""
    import bpy
    mat = bpy.data.materials.new(name)
    nt = mat.node_tree
    nt.nodes.clear()
    em = nt.nodes.new("ShaderNodeEmission")
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    nt.links.new(em.outputs[0], out.inputs[0])
    nt.links.new(build(nt), em.inputs["Color"])
    return mat


def ortho_camera(scene, width, location):
    """An orthographic camera `width` wide at `location`, looking down −Z: the scene's."""
    import bpy
    cam_data = bpy.data.cameras.new("cam")
    cam_data.type = "ORTHO"
    cam_data.ortho_scale = width
    cam = bpy.data.objects.new("cam", cam_data)
    scene.collection.objects.link(cam)
    cam.location = location
    scene.camera = cam
    return cam


def cycles_to_exr(scene, size, samples):
    """Cycles on the CPU, `samples` a pixel (fixed seed, no denoising), size² pixels, written
    as linear 32-bit float EXR with the Standard view: the emitted values as they are."""
    r = scene.render
    r.engine = "CYCLES"
    scene.cycles.samples = samples
    scene.cycles.use_denoising = False
    scene.cycles.seed = 0
    scene.cycles.device = "CPU"
    r.resolution_x = r.resolution_y = size
    r.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    r.image_settings.file_format = "OPEN_EXR"
    r.image_settings.color_depth = "32"
