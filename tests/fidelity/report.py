"""Markdown table of the fidelity reports: one row per scene, what Blender does and what we do.

python3 tests/fidelity/report.py [DIR]      (DIR: the reports, default build/fidelity/)
"""
import json
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def blender_summary(report):
    bodies = report.get("bodies", {})
    fell = [n for n, b in bodies.items() if b["bullet"]["fell"]]
    rest = [n for n, b in bodies.items() if b["bullet"]["at_rest"]]
    top = max((b["bullet"]["max_speed_mps"] for b in bodies.values()), default=0.0)
    return f"{len(bodies)} bodies: {len(fell)} fall, {len(rest)} end at rest; fastest {top:.2f} m/s"


def our_summary(report):
    if not report.get("criteria"):
        return f"**{report['verdict']}**: {'; '.join(report['failed'])}"
    parts = []
    for c in report["criteria"]:
        if c["ok"]:
            continue
        items = c["divergent"]
        shown = ", ".join(items[:4]) + (f" (+{len(items) - 4})" if len(items) > 4 else "")
        detail = ""
        if c["criterion"] == "resting_heights":
            shown = ", ".join(f"{n} {c['numbers'][n]['dz_m'] * 100:+.1f} cm" for n in items[:4])
        elif c["criterion"] == "max_speed":
            detail = f" ({c['numbers']['ours_max_mps']} vs {c['numbers']['bullet_max_mps']} m/s)"
        mark = "covered" if c["covered"] else "fails"
        parts.append(f"{c['criterion']} {mark}: {shown}{detail}")
    bodies = report.get("bodies", {})
    apart = max((b.get("final_apart_m") or 0.0 for b in bodies.values()), default=0.0)
    verdict = report["verdict"].split(" (")[0] + (" (covered)" if report["verdict"].startswith("PASS (") else "")
    return f"**{verdict}**" + (": " + "; ".join(parts) if parts else "") + f"; max final distance {apart:.2f} m"


def table(reports):
    rows = ["| scene | what Blender does | what we do |", "|---|---|---|"]
    for r in reports:
        rows.append(f"| {r['scene']} | {r['what']}; {blender_summary(r)} | {our_summary(r)} |")
    return "\n".join(rows)


def main(argv):
    folder = argv[0] if argv else os.path.join(ROOT, "build", "fidelity")
    names = sorted(f for f in os.listdir(folder) if f.endswith(".json"))
    reports = [json.load(open(os.path.join(folder, f))) for f in names]
    order = _scene_order()
    reports.sort(key=lambda r: order.get(r["scene"], len(order)))
    print(table(reports))
    return 0


def _scene_order():
    """Scenes in the order scenes.py lists them, read from its text (this runs without Blender)."""
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "scenes.py")
    text = open(path).read()
    body = text[text.index("SCENES = {"):]
    names = [line.split('"')[1] for line in body.splitlines()[1:] if line.strip().startswith('"')]
    return {name: k for k, name in enumerate(names)}


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
