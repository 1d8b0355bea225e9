"""The painting's material kept current: `sync` compares what was made with what the settings,
images and lights would make now and redoes only what differs (derived images, bakes, the node
tree); `tree` (re)builds the node tree from the graph (`blender/nodes/`), `osl` the Cycles OSL
script that computes the shadows in the shader.
"""
