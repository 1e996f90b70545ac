"""Viewport overlays drawn with the gpu module only."""
from . import paths

classes = ()


def add_handlers():
    paths.OVERLAY.add()


def remove_handlers():
    paths.OVERLAY.remove()
