"""What an artist gives us, read (no bpy; Blender's image loader only on first use): image files
(`imageio`), the names that say each file's channel (`channel_names`), recipes
(`recipe`), what a folder holds (`painting_folder`), layered files (`layered_files`: .ora and
folders of layers → a scene of §15), paintings that move (`painting_frames`: sequences and sprite
sheets read per frame, §16), the samples shipped beside the package (`samples`), the built-in
test painting (`testpainting`) and what a job will need before it is spent (`memory`).

A painting or a layer that comes without a shape image gets one made by `shapes/` (inflated
from its silhouette); nothing here is drawn by hand. A new input format lives here: a reader to
`layered_files.FileLayer`s (a file of layers) or to a folder's channels (one painting).
"""
