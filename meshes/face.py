"""A leaning rock face standing on a ground strip (thesis 4.9.3, D10).

The face is the parallelogram with base [x0, x0 + width] at y = 0 and its top shifted by
``lean * height`` in x; the ground strip [x0 - height, x0 - height + ground_length] x
[-ground_depth, 0] carries it. Structured quadrilaterals: ``nx`` x ``ny`` in the face,
cells of the face's width / nx along the ground, one cell deep. The face's base nodes are
shared with the ground (a bonded base). Physical groups: cells "face", "ground"; boundaries
"base" (y = -ground_depth) and "top" (the face's top).
"""

from hybrid.geometry import physical_group


def build(gmsh, width: float = 1.6, height: float = 10.0, nx: int = 4, ny: int = 25,
          lean: float = 0.08, x0: float = 5.0, ground_length: float = 60.0,
          ground_depth: float = 1.0, cells: str = "quadrilateral") -> None:
    """Create the face and the ground strip (m) in the current gmsh model and mesh it."""
    geo = gmsh.model.geo
    size = width / nx
    gx0, gx1 = x0 - height, x0 - height + ground_length
    p = {k: geo.addPoint(x, y, 0) for k, (x, y) in {
        "g0": (gx0, -ground_depth), "g1": (gx1, -ground_depth), "g2": (gx1, 0.0),
        "f1": (x0 + width, 0.0), "f0": (x0, 0.0), "g3": (gx0, 0.0),
        "t1": (x0 + width + lean * height, height), "t0": (x0 + lean * height, height)}.items()}
    ln = {k: geo.addLine(p[a], p[b]) for k, (a, b) in {
        "base": ("g0", "g1"), "gr": ("g1", "g2"), "s1": ("g2", "f1"), "fb": ("f1", "f0"),
        "s0": ("f0", "g3"), "gl": ("g3", "g0"), "fr": ("f1", "t1"), "ft": ("t1", "t0"),
        "fl": ("t0", "f0")}.items()}

    def n(span: float) -> int:
        return max(int(round(span / size)), 1) + 1

    n0, n1 = n(x0 - gx0), n(gx1 - x0 - width)
    for k, count in (("fb", nx + 1), ("ft", nx + 1), ("fr", ny + 1), ("fl", ny + 1),
                     ("gr", 2), ("gl", 2), ("s0", n0), ("s1", n1),
                     ("base", n0 + nx + n1 - 1)):  # as many nodes as the top side
        geo.mesh.setTransfiniteCurve(ln[k], count)
    face = geo.addPlaneSurface([geo.addCurveLoop([-ln["fb"], ln["fr"], ln["ft"], ln["fl"]])])
    ground = geo.addPlaneSurface([geo.addCurveLoop([ln["base"], ln["gr"], ln["s1"], ln["fb"],
                                                    ln["s0"], ln["gl"]])])
    geo.mesh.setTransfiniteSurface(face)
    geo.mesh.setTransfiniteSurface(ground, "Left", [p["g0"], p["g1"], p["g2"], p["g3"]])
    if cells == "quadrilateral":
        geo.mesh.setRecombine(2, face)
        geo.mesh.setRecombine(2, ground)
    geo.synchronize()
    physical_group(gmsh, 2, [face], "face")
    physical_group(gmsh, 2, [ground], "ground")
    physical_group(gmsh, 1, [ln["base"]], "base")
    physical_group(gmsh, 1, [ln["ft"]], "top")
    gmsh.model.mesh.generate(2)
