"""The cos-θ shadow images (pipeline.md §13, §15) baked with numpy: for a painting
(`shadow_images`: what is stale, baking it, the kept bakes of a moving painting), while a light
is dragged (`live_bake`: a worker thread, draft then final) and for a layer's whole group at
once (`layers`: the core Scene built from the group's planes).
"""
