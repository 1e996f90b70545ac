"""A library being browsed: the open file, which worlds match, and decoded data of one world.

Queries (added on top of this) only change `matching`; drawing and lists read it. Every change of
data or match state bumps `version` so cached GPU batches know when to rebuild.
"""
import json

import numpy as np

from . import family as core_family


class LibraryView:
    """An open .mwb library and the browsing state that is not saved with the .blend."""

    def __init__(self, native, path):
        self.path = path
        self.library = native.Library(path)
        self.scene = json.loads(self.library.header["scene_json"])
        self.body_names = [b["name"] for b in self.scene.get("bodies", [])]
        self.body_types = [b["type"] for b in self.scene.get("bodies", [])]
        self.body_kinematic = [bool(b.get("kinematic", False)) for b in self.scene.get("bodies", [])]
        world = self.scene.get("world", {})
        self.frame_start = int(world.get("frame_start", 1))
        self.fps = float(world.get("fps", 24.0))
        self.world_indices = []
        self.matching = np.zeros(0, dtype=bool)
        self.version = 0
        self._decoded = {}
        self._lineages = {}
        self._add_worlds()

    def _add_worlds(self):
        ids = list(self.library.world_indices)
        added = len(ids) - len(self.world_indices)
        if added > 0:
            self.world_indices = ids
            # A new world matches until a query says otherwise.
            self.matching = np.concatenate([self.matching, np.ones(added, dtype=bool)])
            self.version += 1
        return added

    def poll(self):
        """Read worlds the engine appended since the last call; returns how many arrived."""
        self.library.poll()
        return self._add_worlds()

    def lineages(self):
        """{world: core.family.Lineage} of every world; read once per world (worlds never change)."""
        for world in self.world_indices:
            if world not in self._lineages:
                self._lineages[world] = core_family.lineage_of(self.library, world)
        return self._lineages

    def family(self, world):
        """{world: relation} of `world`'s root, ancestors, itself and children (core.family)."""
        return core_family.family(self.lineages(), world)

    def set_matching(self, flags):
        """Replace the per-world match flags (file order); drawing rebuilds on the next redraw."""
        flags = np.asarray(flags, dtype=bool)
        if flags.shape != (len(self.world_indices),):
            raise ValueError(f"matching needs shape ({len(self.world_indices)},), got {flags.shape}")
        self.matching = flags
        self.version += 1

    def simulated_bodies(self):
        """Indices of the bodies the simulation moves (ACTIVE, not animated)."""
        return [i for i, (t, k) in enumerate(zip(self.body_types, self.body_kinematic)) if t == "ACTIVE" and not k]

    def world_summary(self, world):
        """A few per-world numbers for lists: summed over the simulated bodies."""
        metrics = self.library.metrics(world)
        bodies = self.simulated_bodies()

        def total(name):
            values = metrics.get(name, [])
            return float(sum(values[i] for i in bodies if i < len(values)))

        return {"rest_s": max((self.library.rest_times(world)[i] for i in bodies), default=0.0),
                "collisions": int(total("collision_count")),
                "travel_m": total("path_length_m")}

    def decoded(self, world):
        """(positions (bodies, frames, 3), orientations (bodies, frames, 4), record_hz), cached for one world."""
        if world not in self._decoded:
            self._decoded.clear()
            info = self.library.world_info(world)
            self._decoded[world] = (self.library.positions(world), self.library.orientations(world),
                                    float(info["record_hz"]))
        return self._decoded[world]
