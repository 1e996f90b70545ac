"""Operators grouped by what the user does: sampling, browsing, querying, refining."""
from . import browsing, querying, refining, sampling

classes = (*sampling.classes, *browsing.classes, *querying.classes, *refining.classes)
