"""A slope on a foundation layer (thesis 3.4.4, C4; C9).

Toe at (toe_x, 0), crest at (toe_x + height / tan(angle), height); foundation down to
y = -foundation_depth; ground flat beyond toe and crest over ``toe_x`` and ``crest_length``.
Physical groups: cells "soil"; boundaries "base", "left", "right", "surface" (the whole ground
line: toe flat, slope face, crest flat).
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
    pts = [geo.addPoint(x, y, 0, size) for x, y in (
        (0, -foundation_depth), (right_x, -foundation_depth), (right_x, height),
        (crest_x, height), (toe_x, 0), (0, 0))]
    lines = [geo.addLine(pts[i], pts[(i + 1) % 6]) for i in range(6)]
    soil = geo.addPlaneSurface([geo.addCurveLoop(lines)])
    geo.synchronize()
    if cells == "quadrilateral":
        quad_options(gmsh)
    physical_group(gmsh, 2, [soil], "soil")
    physical_group(gmsh, 1, [lines[0]], "base")
    physical_group(gmsh, 1, [lines[1]], "right")
    physical_group(gmsh, 1, [lines[2], lines[3], lines[4]], "surface")
    physical_group(gmsh, 1, [lines[5]], "left")
    gmsh.model.mesh.generate(2)
