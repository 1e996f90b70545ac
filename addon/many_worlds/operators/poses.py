"""Pose parts of the goal: adding one for the selected objects, and keeping the pose an object has
now (As Posed). A pose part sits in the boxes' list; removing, ordering and switching it on or off
are the boxes' operators."""
import bpy
from bpy.props import BoolProperty, EnumProperty, IntProperty

from .. import pose_parts, props, scene_boxes
from ..core import pose_target
from .boxes import part_at


class MWB_OT_add_pose(bpy.types.Operator):
    """Add a pose part for the selected objects the simulation moves: keep the worlds where they
    face the way it says (upright by default; a negative part: where they never do)"""
    bl_idname = "mwb.add_pose"
    bl_label = "Add Pose"
    bl_options = {"REGISTER", "UNDO"}

    mode: EnumProperty(name="Pose", items=props.POSE_MODE_ITEMS, default=pose_target.UPRIGHT,
                       description="Which way the objects should face (As Posed: one part per object)")
    negative: BoolProperty(name="Negative", default=False,
                           description="Keep the worlds where the objects never hold the pose")

    @classmethod
    def poll(cls, context):
        if not hasattr(context.scene, "mwb"):
            return False
        problem = scene_boxes.new_pose_problem(context)
        if problem:
            cls.poll_message_set(problem)
        return not problem

    def execute(self, context):
        names, left_out = scene_boxes.pose_body_choice(context)
        if left_out:
            self.report({"WARNING"}, scene_boxes.left_out_text(left_out))
        # A captured pose is one object's: As Posed makes a part per object.
        groups = [[name] for name in names] if self.mode == pose_target.AS_POSED else [names]
        for group in groups:
            scene_boxes.store_pose(context.scene, group, self.mode, self.negative)
        scene_boxes.refresh(context.scene)
        self.report({"INFO"}, scene_boxes.match_text() or "Pose stored; open a library to query it")
        return {"FINISHED"}


class MWB_OT_pose_use_current(bpy.types.Operator):
    """Keep the pose the part's object has now, at this frame (while previewing, the world's pose):
    the side of it facing up stays up"""
    bl_idname = "mwb.pose_use_current"
    bl_label = "Use Current Pose"
    bl_options = {"REGISTER", "UNDO"}

    index: IntProperty(name="Index", default=-1, description="Pose part to change; -1: the active one")

    def execute(self, context):
        _, part = part_at(context, self.index)
        if part is None or part.kind != "POSE":
            self.report({"ERROR"}, "Choose a pose part in the list first")
            return {"CANCELLED"}
        if not pose_parts.capture(part):
            self.report({"ERROR"}, "None of the part's objects is in the file any more")
            return {"CANCELLED"}
        scene_boxes.set_quietly(part, "pose_mode", pose_target.AS_POSED)
        scene_boxes.refresh(context.scene)
        return {"FINISHED"}


classes = (MWB_OT_add_pose, MWB_OT_pose_use_current)
