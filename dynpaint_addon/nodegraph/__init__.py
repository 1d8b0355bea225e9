"""Node graphs of the pipeline, no bpy: one backend-neutral description (graph.py; the terms
in pipeline_graph.py, built of the node groups in subgraphs.py), what a painting needs of it
(features.py, derived_inputs.py) and the text generators (text_codegen.py → osl_codegen.py,
glsl_codegen.py) with their hand-written snippets by language (snippets/). Blender's node
trees are built from it in blender/nodes/."""
