"""The list of stored worlds."""
import bpy


class MWB_UL_worlds(bpy.types.UIList):
    """One row per world: index, when it came to rest, collisions, how far the bodies travelled."""

    def draw_item(self, context, layout, data, item, icon, active_data, active_propname, index=0, flt_flag=0):
        row = layout.row(align=True)
        row.label(text=f"World {item.world_index}")
        row.label(text=f"rest {item.rest_s:.2f} s")
        row.label(text=f"{item.collisions} hits")
        row.label(text=f"{item.travel_m:.2f} m")


classes = (MWB_UL_worlds,)
