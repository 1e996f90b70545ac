"""Operators grouped by what the user does: sampling and browsing."""
from . import browsing, sampling

classes = (*sampling.classes, *browsing.classes)
