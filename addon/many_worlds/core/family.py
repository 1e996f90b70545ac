"""A world's family in a library with refined worlds: where it came from and what came of it.

Sampled worlds are roots (parent -1). A refined world has one parent and a branch time; its
ancestors lead back to one root. Browsing a family shows the root, every ancestor, the world
itself and its children, so the user can compare refinements and walk back up. No bpy here.
"""
from dataclasses import dataclass

SELECTED, ROOT, ANCESTOR, CHILD = "SELECTED", "ROOT", "ANCESTOR", "CHILD"


@dataclass(frozen=True)
class Lineage:
    """Where one world came from: parent -1 and branch 0 s for a sampled world."""
    world: int
    parent: int
    branch_time_s: float
    root: int


def lineage_of(library, world):
    info = library.world_info(world)
    return Lineage(int(world), int(info["parent_world"]), float(info["branch_time_s"]), int(info["root_world"]))


def ancestors(lineages, world):
    """Parent, grandparent, ... up to the root (nearest first); a world missing from `lineages` ends the walk."""
    chain, seen = [], {world}
    parent = lineages[world].parent if world in lineages else -1
    while parent >= 0 and parent in lineages and parent not in seen:
        chain.append(parent)
        seen.add(parent)
        parent = lineages[parent].parent
    return chain


def family(lineages, world):
    """{world index: SELECTED | ROOT | ANCESTOR | CHILD} of `world`'s family; {} if it is unknown.

    `lineages` maps every world index of the library to its Lineage.
    """
    if world not in lineages:
        return {}
    members = {w: CHILD for w, line in lineages.items() if line.parent == world}
    chain = ancestors(lineages, world)
    for k, ancestor in enumerate(chain):
        members[ancestor] = ROOT if k == len(chain) - 1 else ANCESTOR
    members[world] = SELECTED
    return members


def depth(lineages, world):
    """Generations between `world` and its root (0 for a sampled world)."""
    return len(ancestors(lineages, world))


def relation_text(line):
    """'sampled' or 'child of 4 at 1.50 s' for a list row."""
    if line.parent < 0:
        return "sampled"
    return f"child of {line.parent} at {line.branch_time_s:.2f} s"
