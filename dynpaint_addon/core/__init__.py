"""The pure-numpy implementation of pipeline.md (§0–§11, §14): the reference for every backend.

Must never import bpy. Modules by spec section: shape (§2), shading (§3–§5, §7), shadow (§6),
warps (§8–§9), fresnel (§10), pipeline (§11 composite and the whole render), sampling and
colour (§0 lookups and transfer functions), lights (§0 painting frame).
"""
