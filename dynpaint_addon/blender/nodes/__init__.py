"""The graph description (nodegraph/) built as Blender node trees: `build.py` makes the nodes,
groups and layout for any tree; each backend supplies its own pieces (graph.py's pseudo nodes):
`shader_backend.py` the material's (Image Texture lookups, drivers, the output),
`compositor_backend.py` the compositor group's (group inputs, Map UV lookups)."""
