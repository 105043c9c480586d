"""Rectangular block meshed with a structured grid (thesis 3.4.1, C1, C2).

Physical groups: cells "soil"; boundaries "base" (y = 0), "top" (y = height),
"left" (x = 0), "right" (x = width).
"""

from hybrid.geometry import physical_group


def build(gmsh, width: float = 12.0, height: float = 12.0, nx: int = 3, ny: int = 3,
          cells: str = "quadrilateral") -> None:
    """Create the block (m) in the current gmsh model and mesh it."""
    geo = gmsh.model.geo
    p = [geo.addPoint(0, 0, 0), geo.addPoint(width, 0, 0),
         geo.addPoint(width, height, 0), geo.addPoint(0, height, 0)]
    base, right, top, left = (geo.addLine(p[0], p[1]), geo.addLine(p[1], p[2]),
                              geo.addLine(p[2], p[3]), geo.addLine(p[3], p[0]))
    surface = geo.addPlaneSurface([geo.addCurveLoop([base, right, top, left])])
    for line, n in ((base, nx), (top, nx), (left, ny), (right, ny)):
        geo.mesh.setTransfiniteCurve(line, n + 1)
    geo.mesh.setTransfiniteSurface(surface)
    if cells == "quadrilateral":
        geo.mesh.setRecombine(2, surface)
    geo.synchronize()
    physical_group(gmsh, 2, [surface], "soil")
    for line, name in ((base, "base"), (top, "top"), (left, "left"), (right, "right")):
        physical_group(gmsh, 1, [line], name)
    gmsh.model.mesh.generate(2)
