"""A library being browsed: the open file, which worlds match, and decoded data of one world.

Queries (added on top of this) only change `matching`; drawing and lists read it. Every change of
data or match state bumps `version` so cached GPU batches know when to rebuild.

Bodies come from the library's current scene (`Library.scene_json`): the sampled scene plus every
body added to worlds since, appended, so a body's index never changes. Not every body exists in
every world: `present(world)` says which do (a body removed in a world's lineage, or added only
in another family or later, is absent; its rows in the world's arrays are NaN). An object changed
after sampling and updated in some worlds has a body per definition ("Ball", "Ball#2"); each
stands for the same object, so `body_names` (the objects' names) can repeat, while a world has at
most one body of each object.
"""

import numpy as np

from . import family as core_family


class LibraryView:
    """An open .mwb library and the browsing state that is not saved with the .blend."""

    def __init__(self, native, path):
        self.path = path
        self._native = native
        self.library = native.Library(path)
        self.world_indices = []
        self.matching = np.zeros(0, dtype=bool)
        self.version = 0
        self.scene_revision = 0
        self._lineages = {}
        self._present = {}
        self._read_scene()
        self.frame_start = int(self.scene.frame_start)
        self.fps = float(self.scene.fps)
        # Recorded frames of the whole run: a world that ended at rest holds its last pose until here.
        self.run_frame_count = int(self.library.run_last_frame) + 1
        self._add_worlds()

    def _read_scene(self):
        """Bodies of the library's current scene (all bodies ever added), as the module reads them."""
        self.scene_json = self.library.scene_json
        self.scene = self._native.Scene.from_json(self.scene_json)
        # The object each body stands for: the names of objects in the .blend.
        self.body_names = list(self.scene.body_objects)
        self._simulated = list(self.scene.simulated_bodies)
        # Presence lists have one entry per body: computed again for the longer list.
        self._present = {}
        self.scene_revision += 1

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
        """Read worlds (and bodies added to worlds) the engine appended since the last call;
        returns how many worlds arrived."""
        self.library.poll()
        if self.library.body_count != len(self.body_names):
            self._read_scene()
            self.version += 1
        return self._add_worlds()

    def present(self, world):
        """bool (bodies,): which bodies exist in `world`; read once per world and scene revision."""
        if world not in self._present:
            self._present[world] = np.asarray(self.library.present(world), dtype=bool)
        return self._present[world]

    def object_bodies(self, world):
        """{object name: body index} of every object of the library: the body `world` has, or (for an
        object the world lacks) its first body."""
        present = self.present(world)
        out = {}
        for i, name in enumerate(self.body_names):
            if name not in out or (present[i] and not present[out[name]]):
                out[name] = i
        return out

    def present_bodies(self, world, bodies):
        """The body indices of `bodies` that exist in `world`, in the given order."""
        present = self.present(world)
        return tuple(b for b in bodies if b < len(present) and present[b])

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
        """Replace the per-world match flags (file order); drawing rebuilds on the next redraw when
        they changed."""
        flags = np.asarray(flags, dtype=bool)
        if flags.shape != (len(self.world_indices),):
            raise ValueError(f"matching needs shape ({len(self.world_indices)},), got {flags.shape}")
        if np.array_equal(flags, self.matching):
            # The same answer (a query repeated as the index fills): nothing to draw again.
            return
        self.matching = flags
        self.version += 1

    def simulated_bodies(self):
        """Indices of the bodies the simulation moves (the engine's BodyRole.SIMULATED), in any world."""
        return list(self._simulated)

    def world_summary(self, world):
        """A few per-world numbers for lists: summed over the simulated bodies the world has."""
        metrics = self.library.metrics(world)
        bodies = self.present_bodies(world, self.simulated_bodies())
        rest_times = self.library.rest_times(world)

        def total(name):
            values = metrics.get(name, [])
            return float(sum(values[i] for i in bodies if i < len(values)))

        return {"rest_s": max((rest_times[i] for i in bodies if i < len(rest_times)), default=0.0),
                "collisions": int(total("collision_count")),
                "travel_m": total("path_length_m")}

    def record_hz(self, world):
        """The rate the world's frames were recorded at (frames per second)."""
        return float(self.library.world_info(world).record_hz)
