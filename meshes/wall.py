"""Backfill behind a retaining wall, on a ground layer that runs on in front of the wall (H3).

The wall face is x = 0 from the heel (0, 0) to the top (0, height); the backfill fills
[0, length] x [0, height]; the ground layer [-front, length] x [-depth, 0] lies under it and in
front of the wall, where the collapsed backfill runs out. Physical groups: cells "backfill",
"ground"; boundaries "wall" (the wall face), "base" (y = -depth), "right" (x = length), "left"
(x = -front), "surface" (backfill top and ground in front of the wall), and the interior line
"backfill_base" (y = 0 under the backfill: a rough base while the ground is only a support).

Structured (default): a transfinite grid, cells of about ``size`` [m]. Unstructured
(``structured=False``): every curve is divided into segments of about ``size``, rounded up to
an even number, and the surfaces are meshed freely at ``size``: quadrilaterals by gmsh's
MeshAdapt recombined with blossom full-quad (full-quad recombination needs an even number of
nodes around each surface; unlike plain blossom it leaves no triangles in the thin ground
layer, as in ``meshes/carsington.py``), triangles by gmsh's default mesher. Measured: 1208
quadrilaterals at 0.5 m (the structured grid: 960), smallest corner sine 0.57 (the sheared
quadrilaterals of the two-cell-thick ground layer), 332 and 0.74 at 1 m.
"""

from hybrid.geometry import physical_group, quad_options


def build(gmsh, height: float = 10.0, length: float = 20.0, front: float = 20.0,
          depth: float = 1.0, size: float = 0.5, cells: str = "quadrilateral",
          structured: bool = True) -> None:
    """Create the wall backfill and ground (m) in the current gmsh model and mesh it."""
    geo = gmsh.model.geo
    pt = {}
    for name, (x, y) in {"a": (-front, -depth), "b": (0.0, -depth), "c": (length, -depth),
                         "d": (length, 0.0), "e": (length, height), "f": (0.0, height),
                         "g": (0.0, 0.0), "h": (-front, 0.0)}.items():
        pt[name] = geo.addPoint(x, y, 0, size)
    ln = {k: geo.addLine(pt[k[0]], pt[k[1]]) for k in
          ("ab", "bc", "cd", "de", "ef", "fg", "gd", "gb", "hg", "ah")}

    def n(length_m: float) -> int:  # nodes on a curve of length_m
        segments = max(int(round(length_m / size)), 1)
        return segments + (0 if structured else segments % 2) + 1

    for k, span in (("ab", front), ("hg", front), ("bc", length), ("gd", length),
                    ("ef", length), ("cd", depth), ("gb", depth), ("ah", depth),
                    ("de", height), ("fg", height)):
        geo.mesh.setTransfiniteCurve(ln[k], n(span))
    front_ground = geo.addPlaneSurface([geo.addCurveLoop([ln["ab"], -ln["gb"], -ln["hg"],
                                                          -ln["ah"]])])
    under = geo.addPlaneSurface([geo.addCurveLoop([ln["bc"], ln["cd"], -ln["gd"], ln["gb"]])])
    backfill = geo.addPlaneSurface([geo.addCurveLoop([ln["gd"], ln["de"], ln["ef"], ln["fg"]])])
    if structured:
        for s in (front_ground, under, backfill):
            geo.mesh.setTransfiniteSurface(s)
            if cells == "quadrilateral":
                geo.mesh.setRecombine(2, s)
    geo.synchronize()
    if not structured and cells == "quadrilateral":
        quad_options(gmsh)
        # blossom leaves triangles in the 1 m ground layer at size 1 m; its full-quad variant,
        # with the even numbers of segments above, leaves none
        gmsh.option.setNumber("Mesh.Algorithm", 1)  # MeshAdapt
        gmsh.option.setNumber("Mesh.RecombinationAlgorithm", 3)  # blossom full-quad
    physical_group(gmsh, 2, [backfill], "backfill")
    physical_group(gmsh, 2, [front_ground, under], "ground")
    for name, lines in (("wall", ["fg"]), ("base", ["ab", "bc"]), ("right", ["cd", "de"]),
                        ("left", ["ah"]), ("surface", ["ef", "hg"]),
                        ("backfill_base", ["gd"])):
        physical_group(gmsh, 1, [ln[k] for k in lines], name)
    gmsh.model.mesh.generate(2)
