"""The Seek tests' goal on the quick-start example: the marble in the left bin, the cone in the
middle one and the pill in the right one, each in the run's last second. Rare together (about one
world in a hundred), so a first batch of a few worlds does not meet it yet."""

# Fractions of the scene camera's view over each bin, apart from its neighbours: (x0, y0, x1, y1).
GOAL = (("Marble", (0.32, 0.22, 0.38, 0.40)), ("Cone", (0.40, 0.19, 0.46, 0.37)),
        ("Pill", (0.50, 0.15, 0.557, 0.33)))
LAST_SECOND = (3.0, 4.0)


def add_goal_boxes(frame_px=None):
    """Add the goal's boxes to the open quick-start scene with mwb.add_box; returns the scene's boxes.

    frame_px None: through the camera "Camera" at the render resolution. Else the camera's frame
    (x0, y0, x1, y1) in the pixels of the 3D viewport of the context, which looks through that
    camera: the boxes are drawn in that viewport (the same boxes, and the overlay shows them).
    """
    import bpy
    from many_worlds import cli
    if frame_px is None:
        view, projection, (width, height) = cli.camera_view("Camera")
        frame_px = (0.0, 0.0, width, height)
        through = dict(view_matrix=view.ravel().tolist(), projection_matrix=projection.ravel().tolist(),
                       region_size=(int(width), int(height)))
    else:
        through = {}
    left, bottom, right, top = frame_px
    for body, (x0, y0, x1, y1) in GOAL:
        rect = (left + x0 * (right - left), bottom + y0 * (top - bottom),
                left + x1 * (right - left), bottom + y1 * (top - bottom))
        assert bpy.ops.mwb.add_box(rect=rect, bodies=body, **through) == {"FINISHED"}
        box = bpy.context.scene.mwb.boxes[-1]
        box.use_time_window, box.time_start_s, box.time_end_s = True, *LAST_SECOND
    return bpy.context.scene.mwb.boxes
