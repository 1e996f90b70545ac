"""Operators grouped by what the user does: sampling, browsing, querying."""
from . import browsing, querying, sampling

classes = (*sampling.classes, *browsing.classes, *querying.classes)
