"""Fixtures for tests inside Blender: a fresh factory scene with the add-on registered, and
helpers that build rigid-body scenes the way a user would (operators on real objects)."""
import math
import os
import sys
import time

import bpy
import pytest

# Test helpers shared by the Python and the in-Blender suites.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "shared"))

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


@pytest.fixture(autouse=True)
def fresh_scene():
    """Every test starts from an empty factory scene with the add-on registered, and unregisters it."""
    from factory_scene import factory_scene_with_addon
    with factory_scene_with_addon() as scene:
        yield scene


def override(ob):
    return bpy.context.temp_override(object=ob, active_object=ob, selected_objects=[ob],
                                     selected_editable_objects=[ob])


def ensure_world(scene=None):
    scene = scene or bpy.context.scene
    if scene.rigidbody_world is None:
        bpy.ops.rigidbody.world_add()
    rbw = scene.rigidbody_world
    if rbw.collection is None:
        rbw.collection = bpy.data.collections.new("RigidBodyWorld")
    return rbw


def add_rigid_body(ob, body_type="ACTIVE", shape="BOX", **settings):
    ensure_world()
    with override(ob):
        bpy.ops.rigidbody.object_add(type=body_type)
    ob.rigid_body.collision_shape = shape
    for key, value in settings.items():
        setattr(ob.rigid_body, key, value)
    return ob


def mesh_object(name, primitive="cube", location=(0, 0, 0), rotation=(0, 0, 0), scale=(1, 1, 1), **kwargs):
    getattr(bpy.ops.mesh, f"primitive_{primitive}_add")(location=location, rotation=rotation, **kwargs)
    ob = bpy.context.active_object
    ob.name = name
    ob.scale = scale
    bpy.context.view_layer.update()
    return ob


def mesh_from_data(name, vertices, faces, location=(0, 0, 0), scale=(1, 1, 1)):
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(vertices, [], faces)
    ob = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(ob)
    ob.location = location
    ob.scale = scale
    bpy.context.view_layer.update()
    return ob


def add_constraint(name, kind, a, b, location=(0, 0, 0), rotation=(0, 0, 0)):
    ensure_world()
    ob = bpy.data.objects.new(name, None)
    bpy.context.scene.collection.objects.link(ob)
    ob.location = location
    ob.rotation_euler = rotation
    # The operator acts on the view layer's active object, not only the context override.
    bpy.context.view_layer.objects.active = ob
    with override(ob):
        bpy.ops.rigidbody.constraint_add(type=kind)
    ob.rigid_body_constraint.object1 = a
    ob.rigid_body_constraint.object2 = b
    bpy.context.view_layer.update()
    return ob


def drop_scene(bodies=2, frame_end=49):
    """A ground and `bodies` boxes dropped from 1 m with some spread: a quick scene to sample."""
    ground = mesh_object("Ground", location=(0, 0, -0.5), scale=(5, 5, 0.5))
    add_rigid_body(ground, "PASSIVE")
    boxes = []
    for i in range(bodies):
        box = mesh_object(f"Box{i}", location=(0.6 * i, 0, 1.0 + 0.3 * i), scale=(0.1, 0.1, 0.1))
        add_rigid_body(box, "ACTIVE", mass=0.5)
        v = box.mwb_variation
        v.location_min, v.location_max = (-0.1, -0.1, 0), (0.1, 0.1, 0.1)
        v.angular_velocity_min, v.angular_velocity_max = (-2, -2, -2), (2, 2, 2)
        boxes.append(box)
    scene = bpy.context.scene
    scene.rigidbody_world.point_cache.frame_start = 1
    scene.rigidbody_world.point_cache.frame_end = frame_end
    scene.frame_start, scene.frame_end = 1, frame_end
    return ground, boxes


def save_blend(tmp_path, name="shot.blend"):
    path = str(tmp_path / name)
    bpy.ops.wm.save_as_mainfile(filepath=path)
    return path


def sample_and_wait(count, timeout_s=180, **settings):
    """Press Sample (the real operator and engine child process) and pump the poller to the end."""
    from many_worlds.core.session import SESSION
    from many_worlds.operators import run_poller
    mwb = bpy.context.scene.mwb
    mwb.world_count = count
    for key, value in settings.items():
        setattr(mwb, key, value)
    assert bpy.ops.mwb.sample() == {"FINISHED"}
    assert SESSION.run is not None
    deadline = time.monotonic() + timeout_s
    while run_poller.poll_run() is not None:
        assert time.monotonic() < deadline, "sampling did not finish in time"
        time.sleep(0.05)
    return SESSION


def cancel_after_finished(count=2, timeout_s=60, ready=None):
    """Let the running engine child finish `count` worlds (or, given `ready`, pump the poller until
    ready() is true), press Cancel, and pump the poller until the run has ended."""
    from many_worlds.core.session import SESSION
    from many_worlds.operators import run_poller
    if ready is None:
        def ready():
            return SESSION.run.progress()[0] >= count
    deadline = time.monotonic() + timeout_s
    while not ready():
        assert time.monotonic() < deadline, "the engine did not make its worlds in time"
        run_poller.poll_run()
        time.sleep(0.05)
    assert bpy.ops.mwb.cancel_sampling() == {"FINISHED"}
    while run_poller.poll_run() is not None:
        assert time.monotonic() < deadline, "the engine did not stop in time"
        time.sleep(0.05)


def degrees(radians):
    return radians * 180 / math.pi
