"""Lists: stored worlds, query boxes, and the worlds ranked by a metric."""
import bpy

from .. import queries
from ..draw.boxes import view_matches


class MWB_UL_worlds(bpy.types.UIList):
    """One row per world: index, when it came to rest, collisions, how far the bodies travelled."""

    def draw_item(self, context, layout, data, item, icon, active_data, active_propname, index=0, flt_flag=0):
        row = layout.row(align=True)
        row.label(text=f"World {item.world_index}")
        row.label(text=f"rest {item.rest_s:.2f} s")
        row.label(text=f"{item.collisions} hits")
        row.label(text=f"{item.travel_m:.2f} m")


class MWB_UL_boxes(bpy.types.UIList):
    """One row per query box: enabled, positive/negative, bodies, whether the viewport shows its view."""

    def draw_item(self, context, layout, data, item, icon, active_data, active_propname, index=0, flt_flag=0):
        row = layout.row(align=True)
        row.prop(item, "enabled", text="")
        row.prop(item, "negative", text="", icon="REMOVE" if item.negative else "ADD", toggle=True)
        bodies = ", ".join(b.name for b in item.bodies) or "no bodies"
        extras = (" [t]" if item.use_time_window else "") + (" [swept]" if item.swept else "")
        row.label(text=f"Box {index + 1}: {bodies}{extras}")
        region_3d = getattr(context.space_data, "region_3d", None)
        area = context.area
        window_region = next((r for r in area.regions if r.type == "WINDOW"), None) if area else None
        if region_3d is not None and window_region is not None and not view_matches(item, window_region, region_3d):
            # Drawn through another view: not shown in the overlay; View Box goes back to it.
            row.operator("mwb.view_box", text="", icon="HIDE_ON", emboss=False).index = index
        row.operator("mwb.remove_box", text="", icon="X", emboss=False).index = index


class MWB_UL_ranking(bpy.types.UIList):
    """The stored worlds ordered by the ranking metric; worlds the boxes reject are hidden (unless
    the metric is Constraints Satisfied). Clicking a row previews that world."""

    def filter_items(self, context, data, propname):
        ranking = queries.RANKING.get(context)
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
        ranking = queries.RANKING.get(context)
        row_index = ranking.position.get(item.world_index)
        metric = context.scene.mwb.rank_metric
        lq = queries.library_query()
        box_count = lq.result.box_count if lq is not None and lq.result is not None else 0
        row = layout.row(align=True)
        row.label(text=f"{row_index + 1 if row_index is not None else '-'}.  World {item.world_index}")
        if row_index is not None:
            row.label(text=queries.format_metric(metric, ranking.values[row_index], box_count))


classes = (MWB_UL_worlds, MWB_UL_boxes, MWB_UL_ranking)
