"""A granular column against a back wall on a floor, for the column-collapse test (R1).

The column [0, length] x [0, height] stands on the floor [-wall, runway] x [-depth, 0] with its
back against the wall [-wall, 0] x [0, height]; its right side (x = length) is the gate. The
column is meshed with ``nx`` x ``ny`` structured cells (``structured``) or with unstructured
cells of the same size on its sides (gmsh's default algorithm, recombined for quadrilaterals);
the wall with one cell across and the column's rows up; the floor one cell deep with cells of
the column's width / nx along it.
With ``roughness`` > 0 the floor's top under the column and along the runway is a sawtooth
(a triangle wave of wavelength two cells, ``roughness`` [m] from valley to peak, about y = 0,
one edge a cell, so that the column's grains keep their size and, for an even ``nx``, the
floor's mean level and the column's area stay those of the flat floor): a stand-in for the
layer of grains fixed to a base with which DEM practice roughens it, so that a grain slides
on it only by riding over the teeth or by shearing the packing above them. The floor is then
meshed with unstructured triangles, and the column can be neither structured nor of
quadrilaterals (gmsh's recombination leaves triangles beside the teeth).
Column, wall and floor share their nodes on the lines they have in common. Physical groups:
cells "column", "wall", "floor"; boundaries "base" (y = -depth), "back" (x = -wall) and "gate"
(the column's right side).
"""

from hybrid.geometry import physical_group


def build(gmsh, length: float = 0.2, height: float = 0.1, nx: int = 20, ny: int = 10,
          runway: float = 1.0, wall: float = 0.02, depth: float = 0.02,
          cells: str = "quadrilateral", structured: bool = True,
          roughness: float = 0.0) -> None:
    """Create the column, the wall and the floor (m) in the current gmsh model and mesh it."""
    if runway <= length:
        raise ValueError(f"runway = {runway} m must reach beyond the column (length = {length} m)")
    size = length / nx
    if roughness < 0 or roughness >= min(depth, size):
        raise ValueError(f"roughness = {roughness} m must be >= 0 and below the floor's depth "
                         f"({depth} m) and the cell size ({size} m)")
    if roughness > 0 and (structured or cells != "triangle"):
        raise ValueError("a rough floor (roughness > 0) needs an unstructured column of "
                         "triangles: give structured=False, cells='triangle'")
    geo = gmsh.model.geo
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
    foot, run = [ln["foot"]], [ln["run"]]
    if roughness > 0:  # the straight foot and runway replaced by sawtooth polylines
        geo.remove([(1, ln["foot"]), (1, ln["run"])])
        foot = _sawtooth(geo, p["g"], p["o"], 0.0, length, nx, 0, roughness)
        run = _sawtooth(geo, p["r"], p["g"], length, runway, n_run - 1, nx, roughness)
    column = geo.addPlaneSurface([geo.addCurveLoop([*(-c for c in reversed(foot)), ln["gate"],
                                                    ln["top"], ln["back_in"]])])
    back_wall = geo.addPlaneSurface([geo.addCurveLoop([ln["wb"], -ln["back"], -ln["wtop"],
                                                       ln["back_in"]])])
    floor = geo.addPlaneSurface([geo.addCurveLoop([ln["base"], ln["fr"], *run, *foot,
                                                   ln["wb"], ln["fl"]])])
    if structured:
        geo.mesh.setTransfiniteSurface(column)
    geo.mesh.setTransfiniteSurface(back_wall)
    if roughness == 0:
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


def _sawtooth(geo, right: int, left: int, x_left: float, x_right: float, cells: int,
              first: int, roughness: float) -> list[int]:
    """Lines from point ``right`` (x_right, y = 0) to point ``left`` (x_left, y = 0): a sawtooth.

    ``cells`` cells along the span, one vertex at the middle of each, at +r/2 and -r/2 in turn
    (r the ``roughness`` [m]; the cell of global index ``first`` + j from x = 0, j counted from
    the left, at +r/2 where that index is even), so that one edge spans each cell (a half cell
    at either end) and the wave runs on across the spans that meet.
    """
    dx = (x_right - x_left) / cells
    pts = [geo.addPoint(x_left + (j + 0.5) * dx,
                        0.5 * roughness * (1.0 if (first + j) % 2 == 0 else -1.0), 0)
           for j in range(cells)]
    pts = [right, *reversed(pts), left]
    lines = [geo.addLine(a, b) for a, b in zip(pts[:-1], pts[1:])]
    for line in lines:
        geo.mesh.setTransfiniteCurve(line, 2)
    return lines
