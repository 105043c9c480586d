"""A column of horizontal layers (lifts) on a structured grid (C10, staged construction).

Physical groups: cells "lift1" ... "liftN" from the bottom up; boundaries "base", "left",
"right", "top" (the top of the last lift).
"""

from hybrid.geometry import physical_group


def build(gmsh, width: float = 2.0, lift_thickness: float = 2.0, lifts: int = 4,
          nx: int = 2, ny_per_lift: int = 2, cells: str = "quadrilateral") -> None:
    """Create the layered column (m) in the current gmsh model and mesh it."""
    geo = gmsh.model.geo
    left_pts = [geo.addPoint(0, k * lift_thickness, 0) for k in range(lifts + 1)]
    right_pts = [geo.addPoint(width, k * lift_thickness, 0) for k in range(lifts + 1)]
    horizontals = [geo.addLine(left_pts[k], right_pts[k]) for k in range(lifts + 1)]
    lefts = [geo.addLine(left_pts[k + 1], left_pts[k]) for k in range(lifts)]
    rights = [geo.addLine(right_pts[k], right_pts[k + 1]) for k in range(lifts)]
    surfaces = []
    for k in range(lifts):
        loop = geo.addCurveLoop([horizontals[k], rights[k], -horizontals[k + 1], lefts[k]])
        surf = geo.addPlaneSurface([loop])
        surfaces.append(surf)
        geo.mesh.setTransfiniteSurface(surf)
        if cells == "quadrilateral":
            geo.mesh.setRecombine(2, surf)
    for line in horizontals:
        geo.mesh.setTransfiniteCurve(line, nx + 1)
    for line in lefts + rights:
        geo.mesh.setTransfiniteCurve(line, ny_per_lift + 1)
    geo.synchronize()
    for k, surf in enumerate(surfaces):
        physical_group(gmsh, 2, [surf], f"lift{k + 1}")
    physical_group(gmsh, 1, [horizontals[0]], "base")
    physical_group(gmsh, 1, [horizontals[-1]], "top")
    physical_group(gmsh, 1, lefts, "left")
    physical_group(gmsh, 1, rights, "right")
    gmsh.model.mesh.generate(2)
