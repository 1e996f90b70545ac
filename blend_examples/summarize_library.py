"""Prints what a library holds: the worlds where the marble ends furthest down the chute and the
ones where the die tumbles most, from the stored metrics and decoded motion."""
import sys

import numpy as np

from many_worlds import _native


def main(path):
    lib = _native.Library(path)
    scene = _native.Scene.from_json(lib.header["scene_json"])
    names = scene.body_names
    marble, die = names.index("Marble"), names.index("Die")
    ends = {w: lib.pose(w, marble, lib.frame_count(w) - 1)[0][0] for w in lib.world_indices}
    spins = {w: lib.metrics(w)["angular_travel_rad"][die] for w in lib.world_indices}
    print(f"{len(ends)} worlds of '{scene.name}', {len(lib.rejections)} rejected")
    print("marble travels furthest along the chute (final x, m):")
    for w in sorted(ends, key=ends.get, reverse=True)[:5]:
        print(f"  world {w:4d}  x = {ends[w]:+.3f}")
    print("die tumbles most (integrated angular speed, rad):")
    for w in sorted(spins, key=spins.get, reverse=True)[:5]:
        print(f"  world {w:4d}  {spins[w]:.1f}")
    xs = np.array(list(ends.values()))
    print(f"marble final x over all worlds: min {xs.min():+.3f}, median {np.median(xs):+.3f}, max {xs.max():+.3f}")


if __name__ == "__main__":
    main(sys.argv[1])
