"""The pure-numpy implementation of pipeline.md (§0–§11, §14): the reference for every backend.

Must never import bpy. Modules by job:

- the render: pipeline (§11 composite, the whole render), input_rules (what the render reads
  of a painting's images: ImageData, masks, silhouette, branches, notes), inputs (§14:
  imperfect images and the guesses about their conventions), shape (§2), shading (§3–§5, §7),
  lights (§0 painting frame, §5 falloff), warps (§8–§9), fresnel (§10), sampling and colour
  (§0 lookups and transfer functions);
- the cos-θ shadows (§6, §13): bake (quality levels), shadow (the reference march),
  crossings (the fast path at every level: the suns' and point lights' grids) and
  crossing_search (the search along a grid's rows); layers (§15: what the layers in front of
  a pixel let through along its ray);
- making the shape from the painting: integrate (normal map → height), laplace (its solver),
  inflate (silhouette → height), photometric (lighting profiles, red/green photos → normals),
  occlusion (ambient occlusion for exported maps).
"""
