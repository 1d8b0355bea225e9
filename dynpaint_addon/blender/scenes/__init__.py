"""Scenes built around paintings: one painting's plane, material, lights and exact camera
(`painting_scene`), a scene of layers (`layered_build`, Add › Layered…), a light turntable
(`turntable`) and the compositor node group (`compositor`). `blender/headless.py` uses them to
render for the command line.
"""
