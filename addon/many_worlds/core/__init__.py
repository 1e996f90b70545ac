"""Blender-free helpers of the add-on: engine process, library access, array shaping, paths.

Nothing in this package imports bpy, so it runs (and is tested) in any Python with numpy.
"""
