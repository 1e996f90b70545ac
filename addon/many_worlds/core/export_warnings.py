"""Export warnings as the panel shows them, without bpy.

The exporter writes one line per object and setting ("Joint: spring_damping_ang: ..."), which the
command line prints as they are. A ragdoll has a dozen joints with the same approximation, so the
panel folds lines that differ only in the object into one line that still names every object.
"""


def grouped_warning_lines(lines, fold_at=3):
    """Lines "object: setting: reason"; those sharing setting and reason with at least `fold_at - 1`
    others become "setting on N objects (A, B, ...): reason", in the order they first appear."""
    groups, order = {}, []
    for line in lines:
        parts = line.split(": ", 2)
        key = (parts[1], parts[2]) if len(parts) == 3 else (None, line)
        if key not in groups:
            groups[key] = []
            order.append(key)
        groups[key].append(parts[0] if len(parts) == 3 else line)
    out = []
    for key in order:
        names = groups[key]
        setting, reason = key
        if setting is None or len(names) < fold_at:
            out.extend(f"{n}: {setting}: {reason}" if setting is not None else n for n in names)
        else:
            out.append(f"{setting} on {len(names)} objects ({', '.join(names)}): {reason}")
    return out
