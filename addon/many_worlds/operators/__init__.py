"""Operators grouped by what the user does: sampling, browsing, querying, refining, changing
which objects exist in worlds."""
from . import browsing, changing, querying, refining, sampling

classes = (*sampling.classes, *browsing.classes, *querying.classes, *refining.classes, *changing.classes)
