"""A granular column against a back wall on a floor, for the column-collapse test (R1).

The column [0, length] x [0, height] stands on the floor [-wall, runway] x [-depth, 0] with its
back against the wall [-wall, 0] x [0, height]; its right side (x = length) is the gate. The
column is meshed with ``nx`` x ``ny`` structured cells (``structured``) or with unstructured
cells of the same size on its sides (gmsh's default algorithm, recombined for quadrilaterals);
the wall with one cell across and the column's rows up; the floor one cell deep with cells of
the column's width / nx along it.
Column, wall and floor share their nodes on the lines they have in common. Physical groups:
cells "column", "wall", "floor"; boundaries "base" (y = -depth), "back" (x = -wall) and "gate"
(the column's right side).
"""

from hybrid.geometry import physical_group


def build(gmsh, length: float = 0.2, height: float = 0.1, nx: int = 20, ny: int = 10,
          runway: float = 1.0, wall: float = 0.02, depth: float = 0.02,
          cells: str = "quadrilateral", structured: bool = True) -> None:
    """Create the column, the wall and the floor (m) in the current gmsh model and mesh it."""
    if runway <= length:
        raise ValueError(f"runway = {runway} m must reach beyond the column (length = {length} m)")
    geo = gmsh.model.geo
    size = length / nx
    p = {k: geo.addPoint(x, y, 0) for k, (x, y) in {
        "b0": (-wall, -depth), "b1": (runway, -depth), "r": (runway, 0.0), "g": (length, 0.0),
        "o": (0.0, 0.0), "w0": (-wall, 0.0), "gt": (length, height), "ot": (0.0, height),
        "wt": (-wall, height)}.items()}
    ln = {k: geo.addLine(p[a], p[b]) for k, (a, b) in {
        "base": ("b0", "b1"), "fr": ("b1", "r"), "run": ("r", "g"), "foot": ("g", "o"),
        "wb": ("o", "w0"), "fl": ("w0", "b0"), "gate": ("g", "gt"), "top": ("gt", "ot"),
        "back_in": ("ot", "o"), "wtop": ("ot", "wt"), "back": ("wt", "w0")}.items()}

    def n(span: float) -> int:
        return max(int(round(span / size)), 1) + 1

    n_run = n(runway - length)
    for k, count in (("foot", nx + 1), ("top", nx + 1), ("gate", ny + 1), ("back_in", ny + 1),
                     ("back", ny + 1), ("wb", 2), ("wtop", 2), ("fr", 2), ("fl", 2),
                     ("run", n_run), ("base", n_run + nx + 1)):
        geo.mesh.setTransfiniteCurve(ln[k], count)
    column = geo.addPlaneSurface([geo.addCurveLoop([-ln["foot"], ln["gate"], ln["top"],
                                                    ln["back_in"]])])
    back_wall = geo.addPlaneSurface([geo.addCurveLoop([ln["wb"], -ln["back"], -ln["wtop"],
                                                       ln["back_in"]])])
    floor = geo.addPlaneSurface([geo.addCurveLoop([ln["base"], ln["fr"], ln["run"], ln["foot"],
                                                   ln["wb"], ln["fl"]])])
    if structured:
        geo.mesh.setTransfiniteSurface(column)
    geo.mesh.setTransfiniteSurface(back_wall)
    geo.mesh.setTransfiniteSurface(floor, "Left", [p["b0"], p["b1"], p["r"], p["w0"]])
    if cells == "quadrilateral":
        for s in (column, back_wall, floor):
            geo.mesh.setRecombine(2, s)
    geo.synchronize()
    physical_group(gmsh, 2, [column], "column")
    physical_group(gmsh, 2, [back_wall], "wall")
    physical_group(gmsh, 2, [floor], "floor")
    physical_group(gmsh, 1, [ln["base"]], "base")
    physical_group(gmsh, 1, [ln["back"]], "back")
    physical_group(gmsh, 1, [ln["gate"]], "gate")
    gmsh.model.mesh.generate(2)
