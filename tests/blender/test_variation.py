"""The variation panel's ± fields: a range entered as ± around the object's value is the min/max
the engine samples from; spin is entered in degrees per second; the bundled example files load
with the ranges they were saved with, shown as ±."""
import glob
import math
import os

import bpy
import pytest

from conftest import ROOT, add_rigid_body, mesh_object

from many_worlds.export import export_scene

EXAMPLES = sorted(glob.glob(os.path.join(ROOT, "blend_examples", "*", "*.blend")))
QUANTITIES = ("location", "rotation", "linear_velocity", "angular_velocity")


def body():
    ob = mesh_object("Die", location=(0, 0, 1))
    return add_rigid_body(ob, "ACTIVE")


def exported_variation(name):
    scene_json = export_scene(bpy.context.scene, bpy.context.evaluated_depsgraph_get()).scene
    return next(b for b in scene_json["bodies"] if b["name"] == name).get("variation", {})


def test_plus_minus_sets_an_even_range_around_the_value():
    v = body().mwb_variation
    v.location_pm = (0.1, 0.2, 0.0)
    assert tuple(v.location_min) == pytest.approx((-0.1, -0.2, 0.0))
    assert tuple(v.location_max) == pytest.approx((0.1, 0.2, 0.0))
    v.rotation_pm = (math.radians(15), 0, 0)
    variation = exported_variation("Die")
    assert variation["location_min_m"] == pytest.approx([-0.1, -0.2, 0.0])
    assert variation["rotation_max_rad"] == pytest.approx([math.radians(15), 0, 0])
    assert variation["rotation_min_rad"] == pytest.approx([-math.radians(15), 0, 0])


def test_spin_is_entered_in_degrees_per_second_and_exported_in_radians():
    v = body().mwb_variation
    v.angular_velocity_pm = (90, 0, 0)
    assert v.angular_velocity_max[0] == pytest.approx(math.pi / 2)
    assert exported_variation("Die")["angular_velocity_min"][0] == pytest.approx(-math.pi / 2)
    v.angular_velocity_max_deg = (180, 0, 0)
    assert v.angular_velocity_max[0] == pytest.approx(math.pi)


def test_an_uneven_range_keeps_its_centre_when_its_plus_minus_changes():
    v = body().mwb_variation
    v.show_min_max = True
    v.linear_velocity_min, v.linear_velocity_max = (0.0, 0, 0), (2.0, 0, 0)
    assert v.linear_velocity_pm[0] == pytest.approx(1.0)
    v.linear_velocity_pm = (0.5, 0, 0)
    assert (v.linear_velocity_min[0], v.linear_velocity_max[0]) == pytest.approx((0.5, 1.5))


@pytest.mark.parametrize("path", EXAMPLES, ids=[os.path.basename(p) for p in EXAMPLES])
def test_example_files_load_with_their_saved_ranges(path):
    bpy.ops.wm.open_mainfile(filepath=path)
    varied = [ob for ob in bpy.data.objects if ob.rigid_body is not None and "mwb_variation" in ob]
    assert varied, "the example has no variation ranges"
    for ob in varied:
        saved = ob["mwb_variation"].to_dict()
        v = ob.mwb_variation
        exported = exported_variation(ob.name)
        for quantity in QUANTITIES:
            low = saved.get(f"{quantity}_min", [0, 0, 0])
            high = saved.get(f"{quantity}_max", [0, 0, 0])
            assert tuple(getattr(v, f"{quantity}_min")) == pytest.approx(low)
            assert tuple(getattr(v, f"{quantity}_max")) == pytest.approx(high)
            # The examples' ranges are even: the panel shows them as ± the saved max.
            assert tuple(getattr(v, f"{quantity}_pm")) == pytest.approx(
                [(b - a) / 2 * (180 / math.pi if quantity == "angular_velocity" else 1) for a, b in zip(low, high)])
            key = {"location": "location_min_m", "rotation": "rotation_min_rad"}.get(quantity, f"{quantity}_min")
            if any(low):
                assert exported[key] == pytest.approx(low)
