"""A Grease Pencil drawing as a scene of lit layers (issue 42; pipeline.md §15, §16).

Grease Pencil cannot be lit (its material is not a BSDF: blender-notes.md). Here each of a
drawing's layers is drawn unlit into an image with its alpha: by numpy (issue 61: strokes.py
reads a layer's strokes on Blender's main thread in milliseconds and draws its fills and
lines in any thread, as Grease Pencil mixes their colours, its edges by exact area), or where
the drawing uses what numpy does not draw (textures, modifiers, effects, blend modes…) by
**Blender's own Grease Pencil renderer**, in a scene of its own so nothing else of the
artist's scene is drawn or changed: Workbench, the Standard view transform (the colours as
drawn), transparent film, an orthographic camera framing the drawing's bounds over all its
frames (so every frame of an animation lands on the same pixels). Each layer is then made a
painting as a plain layer of a layered file is (layered_files.painting_of_frames: a shaded
dark copy, its silhouette inflated by parts; sprite sheets where it changes over the frames),
or a dark image drawn from the shadow colours the artist named ("<name> shadow" layers and
materials), and the layers are built as Add › Layered… builds them (layered_build), where the
drawing is. The lit copy follows its drawing.

One module per step, each importing only those above it in this list:

- reading.py: what the object holds — its layers that draw, shadow colours, depths, frames,
  bounds, digests;
- building.py: a drawing made from data (samples, tests, benchmarks);
- drawing.py: Blender draws each layer (render_layers);
- strokes.py: numpy draws each layer (read_drawing, then ReadDrawing.draw in any thread),
  and what it does not draw (unsupported);
- lit_copy.py: the lit copy made (light_drawing; From Grease Pencil, the command line);
- artist_changes.py: what the artist changed on a lit copy, kept when it is made anew;
- live.py: the lit copy follows its drawing (a stroke's draft, the full redraw after).
"""
