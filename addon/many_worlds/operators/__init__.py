"""Operators grouped by what the user does: sampling, browsing, querying, refining, changing
which objects exist in worlds."""
from . import browsing, changing, boxes, refining, sampling

classes = (*sampling.classes, *browsing.classes, *boxes.classes, *refining.classes, *changing.classes)
