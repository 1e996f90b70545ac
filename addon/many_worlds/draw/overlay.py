"""What every viewport overlay of the add-on shares: one draw callback in the 3D views, added and
removed once."""
import bpy


class ViewportOverlay:
    """Subclasses set `draw_phase` ("POST_VIEW" for world space, "POST_PIXEL" for region pixels)
    and define draw(); remove() calls forget() so an overlay can drop what it cached."""
    draw_phase = "POST_PIXEL"

    def __init__(self):
        self._handle = None

    def add(self):
        if self._handle is None:
            self._handle = bpy.types.SpaceView3D.draw_handler_add(self.draw, (), "WINDOW", self.draw_phase)

    def remove(self):
        if self._handle is not None:
            bpy.types.SpaceView3D.draw_handler_remove(self._handle, "WINDOW")
            self._handle = None
        self.forget()

    def forget(self):
        """Drops whatever the overlay keeps between redraws."""

    @property
    def active(self):
        return self._handle is not None

    def draw(self):
        raise NotImplementedError
