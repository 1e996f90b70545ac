"""Operators grouped by what the user does: sampling, browsing, querying with boxes and poses,
refining, changing which objects exist in worlds, seeking a goal."""
from . import browsing, changing, boxes, poses, refining, run_poller, sampling, seeking

classes = (*run_poller.classes, *sampling.classes, *browsing.classes, *boxes.classes, *poses.classes,
           *refining.classes, *changing.classes, *seeking.classes)
