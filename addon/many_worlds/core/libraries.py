"""Opening a library: the one place a LibraryView is made and becomes the session's. What the
add-on does with it then (list its worlds, apply the boxes, restore the preview) subscribes to
reactions.LIBRARY_OPENED, so this needs no bpy and imports no operator."""
import os

from .. import _native
from . import reactions
from .library_view import LibraryView
from .session import SESSION


def open_library(path, scene=None):
    """Open the library at `path` as the session's view; False (and no view) when there is no file.
    Raises IOError or ValueError for a file that is not a library."""
    SESSION.view = None
    if not path or not os.path.isfile(path):
        return False
    SESSION.view = LibraryView(_native, path)
    reactions.notify(reactions.LIBRARY_OPENED, scene, SESSION.view)
    return True
