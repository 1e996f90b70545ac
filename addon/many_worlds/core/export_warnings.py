"""Export warnings as people read them, without bpy.

The exporter writes one line per object and setting ("Joint: spring_damping_ang: ..."). A Cell
Fracture wall joined with Connect has a hundred constraints with the same approximation, so lines
that differ only in the object fold into one line per setting and reason, which counts the objects
and names the first few: "breaking_threshold on 118 constraints (Constraint, Constraint.001,
Constraint.002, … and 115 more): breaking is approximated ...". The full list stays with the caller
(the command line's --all-warnings, the panel's report).
"""

NAMED = 3  # objects named in a folded line before "… and N more"


def _names(names):
    if len(names) <= NAMED + 1:
        return ", ".join(names)
    return f"{', '.join(names[:NAMED])}, … and {len(names) - NAMED} more"


def grouped_warning_lines(lines, fold_at=3, constraints=frozenset()):
    """Lines "object: setting: reason"; those sharing setting and reason with at least `fold_at - 1`
    others become "setting on N objects (A, B, C, … and K more): reason", in the order they first
    appear ("constraints" when every one is in `constraints`)."""
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
            noun = "constraints" if all(n in constraints for n in names) else "objects"
            out.append(f"{setting} on {len(names)} {noun} ({_names(names)}): {reason}")
    return out
