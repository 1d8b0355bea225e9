"""Dynamic Painting: the numpy reference core (core/), recipes, image I/O and the command line.

Nothing here imports bpy at import time, so the core runs anywhere numpy does; Blender is
loaded only to read PNG/JPEG/TIFF files and, later, by the add-on's own modules.
"""
__version__ = "0.1.0"
