"""Do convex pieces pass through a passive mesh? The Cell Fracture wall of scenes.py on a plane
with a MESH shape (default margin), hit by a thrown ball, sampled with perturbation as the
add-on samples it. A piece tunnelled when its origin ends more than BELOW_M under the plane it
started above. Shared by the fidelity test and tests/bench/bench_tunnel.py."""
import os
import subprocess
import tempfile

import bpy

import scenes

BELOW_M = 0.02  # further under the plane than any resting piece could be


def sample_fracture_wall_on_mesh(worlds):
    """(pieces, stored worlds, worlds with a tunnelled piece, tunnelled pieces) of `worlds` worlds."""
    from many_worlds import _native
    from many_worlds.core import paths
    from many_worlds.export import export_and_validate
    from compare import SCENES_DIR
    if SCENES_DIR:  # saved by an older Blender (save_scenes.py), where Cell Fracture is bundled
        bpy.ops.wm.open_mainfile(filepath=os.path.join(SCENES_DIR, "fracture_wall_on_mesh.blend"), load_ui=False)
    else:
        scenes.fracture_wall(ground_shape="MESH")
    result, problems = export_and_validate(bpy.context)
    assert result.scene is not None and not problems, problems
    with tempfile.TemporaryDirectory() as folder:
        scene_json = os.path.join(folder, "wall.scene.json")
        with open(scene_json, "w") as f:
            f.write(result.to_json())
        library = os.path.join(folder, "wall.mwb")
        subprocess.run([paths.engine_path(), "sample", "--scene", scene_json, "--out", library,
                        "--worlds", f"0:{worlds}"], check=True, capture_output=True)
        lib = _native.Library(library, 0.0)
        names = _native.Scene.from_json(lib.scene_json).body_names
        pieces = [i for i, name in enumerate(names) if name.startswith("Wall_cell")]
        plane_z = 0.0
        tunnelled_worlds = tunnelled_pieces = 0
        for w in lib.world_indices:
            positions = lib.positions(w)
            sunk = [i for i in pieces if positions[i, 0, 2] > plane_z and positions[i, -1, 2] < plane_z - BELOW_M]
            tunnelled_pieces += len(sunk)
            tunnelled_worlds += bool(sunk)
        return len(pieces), len(lib.world_indices), tunnelled_worlds, tunnelled_pieces
