"""What the tests, the benchmarks and the doc generators share, and the extension does not ship
(blender_manifest.toml excludes this folder): a headless Chromium driver (chromium.py), example
paintings in other tools' conventions (example_paintings.py) and test shapes (shapes.py)."""
