"""A world's family in a library with refined worlds: where it came from and what came of it.

Sampled worlds are roots (parent -1). A refined world has one parent and a branch time; its
ancestors lead back to one root. A world made by adding or removing bodies is a child too,
branching at 0 s, and its lineage step names the bodies added and removed. Browsing a family shows
the root, every ancestor, the world itself and its children, so the user can compare refinements
and walk back up. No bpy here.
"""
from dataclasses import dataclass
from typing import Tuple

SELECTED, ROOT, ANCESTOR, CHILD = "SELECTED", "ROOT", "ANCESTOR", "CHILD"


@dataclass(frozen=True)
class Lineage:
    """Where one world came from: parent -1 and branch 0 s for a sampled world. `added` and
    `removed` are the body indices the step that made this world added to or removed from its
    parent (empty for sampled and plainly refined worlds)."""
    world: int
    parent: int
    branch_time_s: float
    root: int
    added: Tuple[int, ...] = ()
    removed: Tuple[int, ...] = ()


def lineage_of(library, world):
    """The Lineage of `world` from the library's WorldInfo."""
    info = library.world_info(world)
    steps = [s for s in info.lineage if int(s.world) == int(world)]
    added, removed = (tuple(steps[-1].added), tuple(steps[-1].removed)) if steps else ((), ())
    return Lineage(int(world), int(info.parent_world), float(info.branch_time_s), int(info.root_world),
                   added, removed)


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


def relation_text(line, body_names=None):
    """'sampled', 'child of 4 at 1.50 s' or 'child of 4: +Ball -Box0' for a list row (body names
    from `body_names`, indices without it)."""
    if line.parent < 0:
        return "sampled"
    if not line.added and not line.removed:
        return f"child of {line.parent} at {line.branch_time_s:.2f} s"

    def name(b):
        return body_names[b] if body_names is not None and 0 <= b < len(body_names) else str(b)

    # An object both removed and added (as another body) was updated: "~Ball".
    removed = {name(b) for b in line.removed}
    added = [name(b) for b in line.added]
    changes = ([f"~{n}" if n in removed else f"+{n}" for n in added] +
               [f"-{n}" for n in sorted(removed - set(added))])
    return f"child of {line.parent}: {' '.join(changes)}"
