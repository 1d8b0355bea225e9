"""A painting as Blender holds it now: its settings (`settings`, the one reading of the
material's properties), its images (`images`: loading, the numpy-made derived images;
`edits`: how many times each input image's pixels were edited in place), its lights
(`lights`), the frame a painting that moves shows (`frames`, `frame_sampling`), what the panel
reports (`status`), and all of it read once per update (`painting_state.read_state`).
The bake reads it; the material's sync decides from it what to redo.
"""
