"""What the add-on does when something happens, without the modules importing each other.

Properties say *that* the user changed something (chose a library, selected a world, edited a
box) and the library service says a library was opened; the modules that know what to do about
it subscribe here when the add-on registers. So properties import none of the modules that import
them, and nothing here needs bpy.
"""
LIBRARY_CHOSEN = "library chosen"    # (scene): the Libraries list's choice changed the library path
LIBRARY_OPENED = "library opened"    # (scene, view): a LibraryView is the session's now
WORLD_SELECTED = "world selected"    # (scene): the Worlds list selected another world
BOXES_CHANGED = "boxes changed"      # (scene): a query box was added, edited or switched

_subscribers = {}


def subscribe(topic, reaction):
    _subscribers.setdefault(topic, []).append(reaction)


def clear():
    """Forget every subscriber (the add-on unregisters)."""
    _subscribers.clear()


def notify(topic, *args):
    for reaction in list(_subscribers.get(topic, ())):
        reaction(*args)
