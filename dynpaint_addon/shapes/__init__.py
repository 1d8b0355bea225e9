"""Shape images made from a painting's images (no bpy, no file reading): the methods
(`maker`: inflate a silhouette, integrate a normal map, normals from a height map, from lighting
profiles or a red/green photograph), their options as one table (`methods`: the command line's
`make-shape` arguments and the add-on's Make Shape both come from it), a figure's relief made
one way for every caller (`relief`: a mask snapped, inflated, embossed, with the effects), a
shape painted in layers (`painted`: Paint Shape's figure mask and height layer) and a method run
on every frame of a painting that moves (`frames`: one floor for all frames, the made frames
kept on disk between passes). The files they read come from `inputs/`; a new shape method is a
function in `maker` and its rows in `methods`.
"""
