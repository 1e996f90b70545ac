"""Panels and lists."""
from . import filmstrip, lists, panels

classes = (*lists.classes, *panels.classes, *filmstrip.classes)
