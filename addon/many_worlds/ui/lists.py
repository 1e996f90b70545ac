"""Lists: stored worlds, the goal's parts (query boxes and poses), and the worlds ranked by a metric."""
import bpy

from .. import scene_boxes
from ..props import part_name
from ..core import family as core_family
from ..core.session import SESSION
from ..draw.boxes import view_matches
from . import filmstrip


_RELATION_ICONS = {core_family.SELECTED: "RADIOBUT_ON", core_family.ROOT: "WORLD",
                   core_family.ANCESTOR: "TRIA_UP", core_family.CHILD: "TRIA_DOWN"}


def family_rows(settings, items):
    """(shown, order) for UIList.filter_items listing the selected world's family, or None to list
    every world in file order. shown: bool per item; order: each item's row, root first, down to
    the children, then the hidden items."""
    view = SESSION.view
    if not settings.family_only or view is None:
        return None
    members = view.family(settings.selected_world)
    lineages = view.lineages()
    shown = [item.world_index in members for item in items]
    keyed = sorted((core_family.depth(lineages, item.world_index), item.world_index, k)
                   for k, item in enumerate(items) if shown[k])
    keyed += [(0, 0, k) for k in range(len(items)) if not shown[k]]
    order = [0] * len(items)
    for row, (_, _, k) in enumerate(keyed):
        order[k] = row
    return shown, order


class MWB_UL_worlds(bpy.types.UIList):
    """One row per world: index, where it came from (refined worlds, objects added or removed),
    when it came to rest, collisions, how far the bodies travelled. With Family of Selected World
    on, only the selected world's root, ancestors and children are listed, indented by generation."""

    def filter_items(self, context, data, propname):
        rows = family_rows(context.scene.mwb, getattr(data, propname))
        if rows is None:
            return [], []
        shown, order = rows
        return [self.bitflag_filter_item if s else 0 for s in shown], order

    def draw_item(self, context, layout, data, item, icon, active_data, active_propname, index=0, flt_flag=0):
        settings = context.scene.mwb
        view = SESSION.view
        lineages = view.lineages() if view is not None else {}
        line = lineages.get(item.world_index)
        row = layout.row(align=True)
        relation = view.family(settings.selected_world).get(item.world_index) if (
            settings.family_only and view is not None) else None
        if relation is not None:
            row.separator(factor=1.5 * core_family.depth(lineages, item.world_index))
        row.label(text=f"World {item.world_index}", icon=_RELATION_ICONS.get(relation, "NONE"))
        if line is not None and line.parent >= 0:
            row.label(text=core_family.relation_text(line, view.body_names))
        row.label(text=f"rest {item.rest_s:.2f} s")
        row.label(text=f"{item.collisions} hits")
        row.label(text=f"{item.travel_m:.2f} m")


class MWB_UL_boxes(bpy.types.UIList):
    """One row per goal part, box or pose: enabled, positive/negative, its kind and number, its order,
    a clock with a time window, whether the viewport shows a box's view. The panel names the active
    part's bodies below the list (a row has no room for names at the sidebar's width)."""

    def draw_item(self, context, layout, data, item, icon, active_data, active_propname, index=0, flt_flag=0):
        row = layout.row(align=True)
        row.prop(item, "enabled", text="")
        row.prop(item, "negative", text="", icon="REMOVE" if item.negative else "ADD", toggle=True)
        after = f" after {item.after_box + 1}" if item.after_box >= 0 else ""
        # The name says the kind: a row has no room for an icon of it at the sidebar's width.
        row.label(text=part_name(item, index) + after)
        if item.use_time_window:
            row.label(text="", icon="TIME")
        if item.kind != "POSE":
            self.draw_view_state(context, row, item, index)
        row.operator("mwb.remove_box", text="", icon="X", emboss=False).index = index

    @staticmethod
    def draw_view_state(context, row, item, index):
        region_3d = getattr(context.space_data, "region_3d", None)
        area = context.area
        window_region = next((r for r in area.regions if r.type == "WINDOW"), None) if area else None
        if region_3d is not None and window_region is not None and not view_matches(item, window_region, region_3d):
            # Drawn through another view: not shown in the overlay; View Box goes back to it.
            row.operator("mwb.view_box", text="", icon="HIDE_ON", emboss=False).index = index


def ranking_columns(layout):
    """(rank, world, value) layouts of one ranking row or of its header: fixed-width columns for
    the rank and the world index, the rest for the value, right-aligned, so the numbers never run
    into each other at the sidebar's default width."""
    split = layout.split(factor=0.17)
    rank = split.row()
    split = split.split(factor=0.27)
    world = split.row()
    value = split.row()
    value.alignment = "RIGHT"
    return rank, world, value


class MWB_UL_ranking(bpy.types.UIList):
    """The stored worlds ordered by the ranking metric; worlds the goal's parts reject are hidden
    (unless the metric is Goal Parts Met). Clicking a row previews that world."""

    def filter_items(self, context, data, propname):
        ranking = scene_boxes.RANKING.get(context)
        items = getattr(data, propname)
        hidden = len(ranking.position)
        flags, order = [], []
        for item in items:
            row = ranking.position.get(item.world_index)
            flags.append(self.bitflag_filter_item if row is not None else 0)
            if row is None:
                row, hidden = hidden, hidden + 1
            order.append(row)
        return flags, order

    def draw_item(self, context, layout, data, item, icon, active_data, active_propname, index=0, flt_flag=0):
        ranking = scene_boxes.RANKING.get(context)
        row_index = ranking.position.get(item.world_index)
        metric = context.scene.mwb.rank_metric
        lq = scene_boxes.library_query()
        box_count = lq.result.box_count if lq is not None and lq.result is not None else 0
        rank, world, value = ranking_columns(layout)
        rank.label(text=f"{row_index + 1}." if row_index is not None else "-")
        world.label(text=str(item.world_index))
        if row_index is not None:
            value.label(text=scene_boxes.format_metric(metric, ranking.values[row_index], box_count, ranking.decimals),
                        **filmstrip.row_icon(context, item.world_index))


class MWB_UL_libraries(bpy.types.UIList):
    """The libraries sampled from this file, one per run (scene and settings); choosing one opens
    it, and Sample adds to it while the scene and settings match it."""

    def draw_item(self, context, layout, data, item, icon, active_data, active_propname, index):
        import os
        row = layout.row()
        row.label(text=os.path.basename(bpy.path.abspath(item.path)), icon="FILE_BLEND")
        if item.interrupted_first >= 0:
            row.label(text="cancelled", icon="PAUSE")


classes = (MWB_UL_worlds, MWB_UL_boxes, MWB_UL_ranking, MWB_UL_libraries)
