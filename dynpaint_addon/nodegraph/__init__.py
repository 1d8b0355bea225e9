"""Node graphs of the pipeline: one backend-neutral description (graph.py, pipeline_graph.py,
no bpy) and the builders that turn it into Blender node trees (build_bpy.py, *_backend.py)."""
