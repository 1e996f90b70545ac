"""Viewport overlays drawn with the gpu module only."""
from . import boxes, paths

classes = ()


def add_handlers():
    paths.OVERLAY.add()
    boxes.OVERLAY.add()


def remove_handlers():
    boxes.OVERLAY.remove()
    paths.OVERLAY.remove()
