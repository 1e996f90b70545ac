"""Every fidelity test starts from an empty factory scene with the add-on registered."""
import os
import sys

import pytest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "shared"))


@pytest.fixture(autouse=True)
def fresh_scene():
    from factory_scene import factory_scene_with_addon
    with factory_scene_with_addon() as scene:
        yield scene
