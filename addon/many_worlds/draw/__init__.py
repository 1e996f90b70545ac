"""Viewport overlays drawn with the gpu and blf modules (no bgl)."""
from . import boxes, paths, poses, world_label

classes = ()


def add_handlers():
    paths.OVERLAY.add()
    boxes.OVERLAY.add()
    poses.OVERLAY.add()
    world_label.OVERLAY.add()


def remove_handlers():
    world_label.OVERLAY.remove()
    poses.OVERLAY.remove()
    boxes.OVERLAY.remove()
    paths.OVERLAY.remove()
