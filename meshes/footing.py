"""Half-space under a strip footing, half model by symmetry (thesis 3.4.2, C3; C5-C7).

Domain 0 <= x <= width, -depth <= y <= 0; the footing loads 0 <= x <= half_footing on the
surface. The mesh is graded: ``fine`` (m) at the footing edge, ``coarse`` (m) far away.
Physical groups: cells "soil"; boundaries "footing", "surface" (free ground beside it),
"symmetry" (x = 0), "right" (x = width), "base" (y = -depth).
"""

from hybrid.geometry import physical_group, quad_options


def build(gmsh, width: float = 20.0, depth: float = 20.0, half_footing: float = 6.0,
          fine: float = 0.5, coarse: float = 2.0, cells: str = "triangle") -> None:
    """Create the footing domain (m) in the current gmsh model and mesh it."""
    geo = gmsh.model.geo
    p0 = geo.addPoint(0, 0, 0, fine)
    p_edge = geo.addPoint(half_footing, 0, 0, fine)
    p_right_top = geo.addPoint(width, 0, 0, coarse)
    p_right_base = geo.addPoint(width, -depth, 0, coarse)
    p_base = geo.addPoint(0, -depth, 0, coarse)
    footing = geo.addLine(p0, p_edge)
    surface = geo.addLine(p_edge, p_right_top)
    right = geo.addLine(p_right_top, p_right_base)
    base = geo.addLine(p_right_base, p_base)
    symmetry = geo.addLine(p_base, p0)
    soil = geo.addPlaneSurface([geo.addCurveLoop([footing, surface, right, base, symmetry])])
    geo.synchronize()
    # mesh size grows linearly with the distance from the footing edge (stress singularity)
    field = gmsh.model.mesh.field
    dist = field.add("Distance")
    field.setNumbers(dist, "PointsList", [p_edge])
    grow = field.add("Threshold")
    field.setNumber(grow, "InField", dist)
    field.setNumber(grow, "SizeMin", fine)
    field.setNumber(grow, "SizeMax", coarse)
    field.setNumber(grow, "DistMin", 0.5 * half_footing)
    field.setNumber(grow, "DistMax", 1.5 * max(width, depth))
    field.setAsBackgroundMesh(grow)
    gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
    if cells == "quadrilateral":
        quad_options(gmsh)
    physical_group(gmsh, 2, [soil], "soil")
    for line, name in ((footing, "footing"), (surface, "surface"), (right, "right"),
                       (base, "base"), (symmetry, "symmetry")):
        physical_group(gmsh, 1, [line], name)
    gmsh.model.mesh.generate(2)
