"""A slope on a foundation layer (thesis 3.4.4, C4; C9).

Toe at (toe_x, 0), crest at (toe_x + height / tan(angle), height); foundation down to
y = -foundation_depth; flat ground over ``toe_x`` before the toe and ``crest_length`` behind the
crest. With ``toe_x = 0`` and ``foundation_depth = 0`` the slope stands on a rigid base at toe
level (Griffiths & Lane 1999). Physical groups: cells "soil"; boundaries "base", "right",
"surface" (toe flat, slope face, crest flat) and "left" (when there is a left side).
"""

import math

from hybrid.geometry import physical_group, quad_options


def build(gmsh, height: float = 10.0, angle: float = 30.0, foundation_depth: float = 10.0,
          toe_x: float = 20.0, crest_length: float = 20.0, size: float = 1.0,
          cells: str = "triangle") -> None:
    """Create the slope (m, angle in degrees) in the current gmsh model and mesh it."""
    geo = gmsh.model.geo
    crest_x = toe_x + height / math.tan(math.radians(angle))
    right_x = crest_x + crest_length
    corners = [((0, -foundation_depth), "base"), ((right_x, -foundation_depth), "right"),
               ((right_x, height), "surface"), ((crest_x, height), "surface"),
               ((toe_x, 0), "surface"), ((0, 0), "left")]
    # drop corners that coincide with the next one (no left side, no foundation layer)
    kept = [(p, name) for i, (p, name) in enumerate(corners)
            if p != corners[(i + 1) % len(corners)][0]]
    tags = [geo.addPoint(x, y, 0, size) for (x, y), _ in kept]
    groups: dict[str, list[int]] = {}
    lines = []
    for i, (_, name) in enumerate(kept):
        line = geo.addLine(tags[i], tags[(i + 1) % len(tags)])
        lines.append(line)
        groups.setdefault(name, []).append(line)
    soil = geo.addPlaneSurface([geo.addCurveLoop(lines)])
    geo.synchronize()
    if cells == "quadrilateral":
        quad_options(gmsh)
    physical_group(gmsh, 2, [soil], "soil")
    for name, members in groups.items():
        physical_group(gmsh, 1, members, name)
    gmsh.model.mesh.generate(2)
