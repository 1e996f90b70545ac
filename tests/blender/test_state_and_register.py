"""Browsing state survives save and reload; register/unregister leaves nothing behind."""
import bpy
import numpy as np

from conftest import drop_scene, sample_and_wait, save_blend
from test_queries import PROJECTION, SIZE, VIEW

import many_worlds
from many_worlds import _native, handlers, preview
from many_worlds.core.session import SESSION
from many_worlds.draw import boxes, paths, poses, world_label
from many_worlds.operators import run_poller


def test_save_and_reopen_restores_library_and_selected_world(tmp_path):
    _, boxes = drop_scene(bodies=1)
    blend = save_blend(tmp_path)
    bpy.context.scene.mwb.library_path = "//worlds/take1.mwb"
    sample_and_wait(3)
    bpy.ops.mwb.select_world(world=2)
    original = np.array(bpy.context.scene.mwb.preview_saved[0].matrix_basis)
    bpy.ops.wm.save_mainfile()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    assert SESSION.view is None
    bpy.ops.wm.open_mainfile(filepath=blend)
    mwb = bpy.context.scene.mwb
    assert mwb.library_path == "//worlds/take1.mwb"
    assert SESSION.view is not None and SESSION.view.path == str(tmp_path / "worlds" / "take1.mwb")
    assert sorted(SESSION.view.world_indices) == [0, 1, 2]
    assert mwb.selected_world == 2 and mwb.worlds[mwb.world_list_index].world_index == 2
    # Still previewing after the reload, and ending it puts the object back where the user had it.
    assert mwb.previewing and bpy.context.scene.rigidbody_world.enabled is False
    bpy.ops.mwb.end_preview()
    box = bpy.data.objects["Box0"]
    assert np.allclose(np.array([v for row in box.matrix_basis for v in row]), original)
    assert bpy.context.scene.rigidbody_world.enabled is True


def our_handlers():
    lists = (bpy.app.handlers.load_post, bpy.app.handlers.frame_change_pre, bpy.app.handlers.undo_post,
             bpy.app.handlers.redo_post, bpy.app.handlers.depsgraph_update_post)
    return [f for handler_list in lists for f in handler_list if f.__module__.startswith("many_worlds")]


def our_keymap_items():
    """The add-on's keymap items (two draw boxes, two step through the ranking) and its toolbar tool's two
    (in a keymap of the default keyconfig)."""
    keyconfigs = bpy.context.window_manager.keyconfigs
    return [item for keyconfig in (keyconfigs.addon, keyconfigs.default) for keymap in keyconfig.keymaps
            for item in keymap.keymap_items if item.idname.startswith("mwb.")]


def query_box_tool_registered():
    from bl_ui.space_toolsystem_common import ToolSelectPanelHelper
    tools = ToolSelectPanelHelper._tool_class_from_space_type("VIEW_3D")._tools["OBJECT"]
    return any(getattr(tool, "idname", None) == "mwb.query_box_tool" for tool in tools if tool is not None)


def test_register_unregister_cycles_leave_no_handlers_timers_or_draw_callbacks(tmp_path):
    # The fixture registered the add-on once; start a run so there is a timer and a child process.
    drop_scene(bodies=1, frame_end=240)
    save_blend(tmp_path)
    mwb = bpy.context.scene.mwb
    mwb.world_count, mwb.threads = 2000, 1
    bpy.ops.mwb.sample()
    run = SESSION.run
    assert bpy.app.timers.is_registered(run_poller.poll_run)
    assert len(our_handlers()) == 5 and all(o.OVERLAY.active for o in (paths, boxes, poses, world_label))
    assert len(our_keymap_items()) == 6 and query_box_tool_registered()
    for _ in range(3):
        many_worlds.unregister()
        assert our_handlers() == [] and our_keymap_items() == [] and not query_box_tool_registered()
        assert not bpy.app.timers.is_registered(run_poller.poll_run)
        assert not any(o.OVERLAY.active for o in (paths, boxes, poses, world_label))
        assert not hasattr(bpy.types, "MWB_OT_sample") and not hasattr(bpy.types.Scene, "mwb")
        assert not hasattr(bpy.types, "MWB_OT_draw_box") and not hasattr(bpy.types, "MWB_UL_ranking")
        assert not hasattr(bpy.types, "MWB_OT_refine_box") and not hasattr(bpy.types, "MWB_OT_go_to_parent")
        assert not hasattr(bpy.types, "MWB_PT_refine") and not hasattr(bpy.types, "MWB_OT_add_pose")
        many_worlds.register()
        assert len(our_handlers()) == 5 and all(o.OVERLAY.active for o in (paths, boxes, poses, world_label))
        assert len(our_keymap_items()) == 6 and query_box_tool_registered()
        assert bpy.context.scene.mwb.world_count == 2000, "saved settings survive re-registration"
    # Unregistering stopped the engine; the worlds it finished are in the file.
    assert run.returncode() is not None and SESSION.run is None
    assert handlers.on_load_post in bpy.app.handlers.load_post
    assert preview.on_frame_change in bpy.app.handlers.frame_change_pre


def test_unregister_stops_a_refinement_and_keeps_its_finished_children(tmp_path):
    drop_scene(bodies=1, frame_end=240)
    save_blend(tmp_path)
    sample_and_wait(1, threads=1, stop_at_rest=False)
    bpy.ops.mwb.select_world(world=0)
    for ob in bpy.context.view_layer.objects:
        ob.select_set(ob.name == "Box0")
    mwb = bpy.context.scene.mwb
    mwb.refine_count, mwb.threads = 5000, 1
    # The whole view: Box0 is inside from the start, so the children branch at 0 s.
    assert bpy.ops.mwb.refine(rect=(0, 0, 1600, 1000), view_matrix=VIEW.ravel().tolist(),
                              projection_matrix=PROJECTION.ravel().tolist(), region_size=SIZE) == {"FINISHED"}
    run = SESSION.run
    assert run is not None and bpy.app.timers.is_registered(run_poller.poll_run)
    many_worlds.unregister()
    assert run.returncode() is not None and SESSION.run is None
    assert not bpy.app.timers.is_registered(run_poller.poll_run)
    library = _native.Library(str(tmp_path / "shot.mwb"))
    assert all(library.world_info(w).parent_world == 0 for w in library.world_indices if w != 0)
    many_worlds.register()
