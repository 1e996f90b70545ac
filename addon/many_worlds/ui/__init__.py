"""Panels and lists."""
from . import lists, panels

classes = (*lists.classes, *panels.classes)
