"""Half-space under a strip footing, half model by symmetry (thesis 3.4.2, C3; C5-C7).

Domain 0 <= x <= width, -depth <= y <= 0; the footing loads 0 <= x <= half_footing on the
surface. The mesh is graded: ``fine`` (m) at the footing edge, ``coarse`` (m) far away.
Physical groups: cells "soil"; boundaries "footing", "surface" (free ground beside it),
"symmetry" (x = 0), "right" (x = width), "base" (y = -depth).

Unstructured (default): gmsh's frontal mesher under a size field growing linearly with the
distance from the footing edge (quadrilaterals by recombination). Structured
(``structured=True``): two transfinite blocks split at x = half_footing, ``fine`` across the
footing and growing geometrically from ``fine`` at the footing edge to about ``coarse`` at
the right side and at the base (a tensor-product grading: the cells below the footing edge
are ``fine`` wide, up to ``coarse`` tall).
"""

import math

from hybrid.geometry import physical_group, quad_options


def build(gmsh, width: float = 20.0, depth: float = 20.0, half_footing: float = 6.0,
          fine: float = 0.5, coarse: float = 2.0, cells: str = "triangle",
          structured: bool = False) -> None:
    """Create the footing domain (m) in the current gmsh model and mesh it."""
    if structured:
        _structured(gmsh, width, depth, half_footing, fine, coarse, cells)
        gmsh.model.mesh.generate(2)
        return
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


def grading(length: float, first: float, last: float) -> tuple[int, float]:
    """Cells and ratio of a geometric grading over ``length`` from ``first`` to about ``last``.

    Sizes first * r^k (k = 0..n-1) sum to ``length`` with the last about ``last``:
    r = (length - first) / (length - last), n = 1 + ln(last / first) / ln r, rounded (at
    least 1); uniform (r = 1, n = length / first rounded) when ``last`` <= ``first`` or the
    length is shorter than ``last``. The ratio is then refitted so that n cells fill the
    length exactly from ``first``.
    """
    if last <= first or length <= last:
        return max(1, round(length / first)), 1.0
    r = (length - first) / (length - last)
    n = max(1, round(1.0 + math.log(last / first) / math.log(r)))
    lo, hi = 1.0, r * 2.0  # sum_{k<n} first r^k = length, increasing in r
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        if first * (mid ** n - 1.0) / (mid - 1.0) < length:
            lo = mid
        else:
            hi = mid
    return n, 0.5 * (lo + hi)


def _structured(gmsh, width, depth, half_footing, fine, coarse, cells) -> None:
    """Two transfinite blocks: 0 <= x <= half_footing and half_footing <= x <= width."""
    geo = gmsh.model.geo
    b = half_footing
    pts = {key: geo.addPoint(x, y, 0) for key, (x, y) in {
        "top0": (0, 0), "top_edge": (b, 0), "top_right": (width, 0),
        "base0": (0, -depth), "base_edge": (b, -depth), "base_right": (width, -depth)}.items()}
    footing = geo.addLine(pts["top0"], pts["top_edge"])
    surface = geo.addLine(pts["top_edge"], pts["top_right"])
    right = geo.addLine(pts["top_right"], pts["base_right"])
    base_right = geo.addLine(pts["base_right"], pts["base_edge"])
    base_left = geo.addLine(pts["base_edge"], pts["base0"])
    symmetry = geo.addLine(pts["base0"], pts["top0"])
    edge = geo.addLine(pts["top_edge"], pts["base_edge"])
    left_block = geo.addPlaneSurface([geo.addCurveLoop([footing, edge, base_left, symmetry])])
    right_block = geo.addPlaneSurface([geo.addCurveLoop([surface, right, base_right, -edge])])
    n_left = max(1, round(b / fine))
    n_right, r_x = grading(width - b, fine, coarse)
    n_down, r_y = grading(depth, fine, coarse)
    # a progression coefficient grows the cells along the curve's direction
    for line, n, coef in ((footing, n_left, 1.0), (base_left, n_left, 1.0),
                          (surface, n_right, r_x), (base_right, n_right, 1.0 / r_x),
                          (right, n_down, r_y), (edge, n_down, r_y),
                          (symmetry, n_down, 1.0 / r_y)):
        geo.mesh.setTransfiniteCurve(line, n + 1, "Progression", coef)
    for block in (left_block, right_block):
        geo.mesh.setTransfiniteSurface(block)
        if cells == "quadrilateral":
            geo.mesh.setRecombine(2, block)
    geo.synchronize()
    physical_group(gmsh, 2, [left_block, right_block], "soil")
    for lines, name in (([footing], "footing"), ([surface], "surface"), ([right], "right"),
                        ([base_right, base_left], "base"), ([symmetry], "symmetry")):
        physical_group(gmsh, 1, lines, name)
