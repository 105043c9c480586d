"""Carsington Dam, cross-section at chainage 725 (thesis chapter 6; Skempton & Vaughan 1993).

Coordinates: x [m] horizontal from the dam axis (core centreline), positive downstream, so the
reservoir (upstream) side is on the left; y [m] is the elevation in m OD. Every default below
is either published or an assumption: see ``docs/carsington.md`` for the list with sources.

Regions (2-D physical groups): "foundation" (mudstone), "yellow_clay" (a thin layer in the
top of the foundation under the upstream shoulder), "core" (rolled clay core with its upstream
boot in a key trench), "zone_I" (inner shoulders, a 1:1 wedge beside the core), "zone_II"
(outer shoulders), "berm" (upstream toe berm). Boundaries (1-D groups): "base", "left",
"right", "crest", "surface" (every free surface: ground, slopes, berm, crest).

Construction lifts: every region above the foundation is cut by the horizontal lines at the
lift tops (:func:`lift_tops`), so each cell lies in one lift, the lift of its centroid's
elevation (``hybrid.continuum.staging.split_into_lifts``; the boot in the key trench is lift
1; the foundation and the yellow clay are in place before construction).
"""

import math
from dataclasses import dataclass

import numpy as np

from hybrid.geometry import physical_group, quad_options

__all__ = ["Section", "build", "lift_tops"]

_NAMES = ("foundation", "yellow_clay", "core", "zone_I", "zone_II", "berm")


@dataclass(frozen=True)
class Section:
    """Dimensions of the cross-section [m, m OD]; defaults: Ch. 725 (see docs/carsington.md).

    Attributes:
        crest_level: design crest [m OD] (thesis, EA: 200.5).
        foundation_level: general foundation level at the axis and downstream [m OD]
            (crest - 36 m: the thesis gives a design height of 35 m (6.1) and an embankment
            "to be 37 m in height" (6.2.4)).
        crest_width: [m] (assumed, 8-10 m suggested).
        upstream_slope, downstream_slope: horizontal per vertical (1:3, 1:2.5: thesis 6.2.2).
        core_top_width: core width at the crest [m] (assumed).
        core_batter: core side batter, horizontal per vertical (assumed 0.25).
        trench_depth: key trench below the foundation level [m] (3 m: thesis 6.2.2).
        boot_length: upstream end of the boot, distance from the axis [m] (assumed).
        boot_height: top of the boot above the foundation level [m] (assumed; the boot is
            trench_depth + boot_height thick).
        zone_I_slope: outer face of Zone I, horizontal per vertical (assumed 1:1).
        berm_top: top of the upstream berm [m OD] (175.6: thesis 6.2.2).
        berm_height: [m] (6 m: thesis 6.2.2); the ground under the berm is berm_top - berm_height.
        berm_width: top width [m] (assumed), berm_slope: its outer face (assumed 1:2.5).
        yellow_clay_thickness: [m] (published 1-2 m; assumed 1.5).
        yellow_clay_length: horizontal length of the layer from the boot's upstream end [m]
            (36: the thesis's 18 yellow-clay elements in one row, each as wide as its core
            elements, about 2 m: core area / 182 elements = 4.2 m2; None: to
            ``yellow_clay_beyond_toe`` beyond the berm toe, the least favourable reading of
            "extensive").
        yellow_clay_beyond_toe: with ``yellow_clay_length`` None, how far the layer runs
            upstream of the berm toe [m] (assumed).
        foundation_depth: base of the model below the foundation level [m] (assumed).
        margin: foundation modelled beyond each toe [m] (assumed: about one base width).
        lifts: construction lifts after the foundation's stage (thesis: six stages, the
            foundation and five lifts; :func:`lift_tops`).
        parts_above: the fill above this level [m OD] placed in parts at most
            ``part_height`` high (None: whole lifts): the fill level of a collapse found more
            finely (:func:`lift_tops`).
        part_height: the largest part's height above ``parts_above`` [m].
    """

    crest_level: float = 200.5
    foundation_level: float = 164.5
    crest_width: float = 10.0
    upstream_slope: float = 3.0
    downstream_slope: float = 2.5
    core_top_width: float = 7.0
    core_batter: float = 0.25
    trench_depth: float = 3.0
    boot_length: float = 35.0
    boot_height: float = 2.0
    zone_I_slope: float = 1.0
    berm_top: float = 175.6
    berm_height: float = 6.0
    berm_width: float = 12.0
    berm_slope: float = 2.5
    yellow_clay_thickness: float = 1.5
    yellow_clay_length: float | None = 36.0
    yellow_clay_beyond_toe: float = 30.0
    foundation_depth: float = 40.0
    margin: float = 200.0
    lifts: int = 5
    parts_above: float | None = None
    part_height: float = 0.5

    def __post_init__(self) -> None:
        if not self.foundation_level < self.berm_top - self.berm_height < self.berm_top \
                < self.crest_level:
            raise ValueError("levels must rise: foundation <= ground under berm < berm top "
                             "< crest")
        if self.lifts < 1:
            raise ValueError("at least one lift")
        lift_tops(self.crest_level, self.berm_top, self.lifts, self.parts_above,
                  self.part_height)  # the parts checked here, before a mesh is built
        for name in ("crest_width", "upstream_slope", "downstream_slope", "core_top_width",
                     "trench_depth", "boot_height", "zone_I_slope", "berm_width",
                     "yellow_clay_thickness", "foundation_depth", "margin"):
            if getattr(self, name) <= 0:
                raise ValueError(f"{name} must be > 0")

    # --- derived points ---------------------------------------------------------------------
    @property
    def height(self) -> float:
        """Embankment height above the general foundation level [m]."""
        return self.crest_level - self.foundation_level

    @property
    def upstream_ground(self) -> float:
        """Ground level under the berm [m OD]."""
        return self.berm_top - self.berm_height

    @property
    def upstream_knee(self) -> tuple[float, float]:
        """Where the upstream shoulder slope meets the ground under the berm; the ground rises
        linearly from the boot end to here and is level upstream of it."""
        y = self.upstream_ground
        return -0.5 * self.crest_width - self.upstream_slope * (self.crest_level - y), y

    @property
    def berm_toe(self) -> float:
        """x of the berm's outer toe [m]."""
        x_top = -0.5 * self.crest_width - self.upstream_slope * (self.crest_level - self.berm_top)
        return x_top - self.berm_width - self.berm_slope * self.berm_height

    @property
    def downstream_toe(self) -> float:
        return 0.5 * self.crest_width + self.downstream_slope * self.height

    @property
    def extent(self) -> tuple[float, float, float]:
        """(x_left, x_right, y_base) of the model [m]."""
        return (self.berm_toe - self.margin, self.downstream_toe + self.margin,
                self.foundation_level - self.foundation_depth)

    def ground(self, x: float) -> float:
        """Original ground level [m OD] at x (level downstream of the boot end and upstream of
        the knee, rising linearly between them)."""
        xk, yk = self.upstream_knee
        x0 = -self.boot_length
        if x >= x0:
            return self.foundation_level
        if x <= xk:
            return yk
        return self.foundation_level + (yk - self.foundation_level) * (x0 - x) / (x0 - xk)

    def core_outline(self) -> list[tuple[float, float]]:
        """Core with its boot, counter-clockwise [m]."""
        half, b, yc = 0.5 * self.core_top_width, self.core_batter, self.crest_level
        boot_top = self.foundation_level + self.boot_height
        trench = self.foundation_level - self.trench_depth
        x_down = half + b * self.height
        return [(-half, yc), (-half - b * (yc - boot_top), boot_top),
                (-self.boot_length, boot_top), (-self.boot_length, trench), (x_down, trench),
                (x_down, self.foundation_level), (half, yc)]

    def window(self, discrete: bool = False) -> tuple[float, float, float, float]:
        """(xmin, ymin, xmax, ymax) [m] of the figures: the dam and some ground; wider for the
        discrete phase, whose upstream slope runs out."""
        if discrete:
            return (self.berm_toe - 40.0, self.foundation_level - 15.0,
                    self.downstream_toe + 20.0, self.crest_level + 5.0)
        return (self.berm_toe - 30.0, self.foundation_level - 25.0, self.downstream_toe + 30.0,
                self.crest_level + 3.0)

    @property
    def crest_range(self) -> tuple[float, float]:
        """x range [m] of the fill top taken as the crest: the crest and 10 m either side."""
        half = 0.5 * self.crest_width + 10.0
        return (-half, half)

    def far_field_point(self) -> tuple[float, float]:
        """A point in the foundation 5 m inside the downstream boundary, half-way down [m]."""
        x_right, y_base = self.extent[1], self.extent[2]
        return (x_right - 5.0, 0.5 * (y_base + self.foundation_level))

    def zones(self, group: np.ndarray, centroid: np.ndarray) -> dict[str, np.ndarray]:
        """Element masks of the post-failure measures from the groups and centroids [m]: the
        core's boot, the core above it, the upstream shoulder (fill upstream of the axis) and
        the embankment (all but the ground)."""
        in_boot = centroid[:, 1] < self.foundation_level + self.boot_height
        return {"boot": (group == "core") & in_boot, "core": (group == "core") & ~in_boot,
                "upstream_shoulder": np.isin(group, ["zone_I", "zone_II", "berm"])
                & (centroid[:, 0] < 0.0),
                "embankment": ~np.isin(group, ["foundation", "yellow_clay"])}

    def node_a_candidates(self) -> dict[str, tuple[float, float]]:
        """Where in the core the thesis's node A may be [m, m OD] (measured beside it).

        The thesis calls it "node A in the core" and compares its displacement with the
        deflection observed "within the core at the base" (6.3.1.2); no more locates it.
        """
        boot_top = self.foundation_level + self.boot_height
        face = 0.5 * self.core_top_width + self.core_batter * (self.crest_level - boot_top)
        return {"axis_foundation_level": (0.0, self.foundation_level),
                "axis_boot_top": (0.0, boot_top), "upstream_face_boot_top": (-face, boot_top),
                "axis_berm_top": (0.0, self.berm_top)}


# fill levels reached in the construction history (thesis 6.2.2): end of 1982 (Elv. 182 at
# Ch. 650-1000), July 1983 (Elv. 190, when the berm was ordered), and the level the thesis
# reports a core displacement at (198 m OD, 6.3.1.2; filling stopped at about Elv. 197 in
# September 1983)
HISTORY_LEVELS = (182.0, 190.0, 198.0)


def lift_tops(crest_level: float = 200.5, berm_top: float = 175.6, lifts: int = 5,
              parts_above: float | None = None, part_height: float = 0.5) -> list[float]:
    """Top elevation of each construction lift [m OD].

    The thesis's six stages are the foundation and five lifts (6.3.1.1). Five lifts (the
    default): the berm top, :data:`HISTORY_LEVELS`, the crest; the first lift brings the
    fill to the berm top with the berm (an assumption: the berm was built in 1983, with the
    fill at 190 m OD; stage 1 keeps it whole). Any other number: the first lift to the berm
    top, then equal lifts to the crest.

    ``parts_above`` (from the berm top to below the crest): each lift's fill above this
    level is placed in equal parts at most ``part_height`` [m] high (the lift is cut at
    ``parts_above`` first), so that a collapse is found at that resolution; the lift tops
    stay among the tops.
    """
    if lifts == 1:
        tops = [crest_level]
    elif lifts == 1 + len(HISTORY_LEVELS) + 1:
        if not berm_top < HISTORY_LEVELS[0] and HISTORY_LEVELS[-1] < crest_level:
            raise ValueError(f"5 lifts use the history levels {HISTORY_LEVELS} m OD: the berm "
                             "top must be below and the crest above them (or give another "
                             "number of lifts)")
        tops = [berm_top, *HISTORY_LEVELS, crest_level]
    else:
        dh = (crest_level - berm_top) / (lifts - 1)
        tops = [berm_top + k * dh for k in range(lifts - 1)] + [crest_level]
    if parts_above is None:
        return tops
    if not (lifts > 1 and berm_top <= parts_above < crest_level and part_height > 0):
        raise ValueError(f"parts_above = {parts_above} m OD must lie from the berm top "
                         f"({berm_top:g}) to below the crest ({crest_level:g}), with two lifts "
                         f"at least and part_height = {part_height} m > 0 (or parts_above "
                         "None: whole lifts)")
    parts = [tops[0]]
    for bottom, top in zip(tops[:-1], tops[1:]):
        start = max(bottom, float(parts_above))
        if start >= top - 1e-6:  # the lift lies wholly below the parts (no sliver at its top)
            parts.append(top)
            continue
        if start > bottom + 1e-6:  # no sliver at its bottom
            parts.append(start)
        else:
            start = bottom
        count = math.ceil((top - start) / part_height - 1e-9)
        parts += [start + k * ((top - start) / count) for k in range(1, count)] + [top]
    return parts


def _polygon(occ, points: list[tuple[float, float]]) -> int:
    tags = [occ.addPoint(x, y, 0) for x, y in points]
    lines = [occ.addLine(tags[i], tags[(i + 1) % len(tags)]) for i in range(len(tags))]
    return occ.addPlaneSurface([occ.addCurveLoop(lines)])


def _outlines(s: Section) -> dict[str, list[tuple[float, float]]]:
    """Region outlines [m]: exact, except the foundation and shoulders (the core is cut out
    of them) and Zone I (a wedge, intersected with the shoulders)."""
    xl, xr, yb = s.extent
    yf, yc, hw = s.foundation_level, s.crest_level, 0.5 * s.crest_width
    xk, yk = s.upstream_knee
    x_boot = -s.boot_length
    x_berm_in = -hw - s.upstream_slope * (yc - s.berm_top)
    t = s.yellow_clay_thickness
    if s.yellow_clay_length is None:
        x_yc = s.berm_toe - s.yellow_clay_beyond_toe
    else:
        x_yc = x_boot - s.yellow_clay_length
    # the ground profile, downstream to upstream
    ground = [(xr, yf), (s.downstream_toe, yf), (x_boot, yf), (xk, yk), (s.berm_toe, yk),
              (xl, yk)]
    x_yc = max(x_yc, xl)
    yc_top = [(x_boot, yf)] + [(x, y) for x, y in ground[3:] if x > x_yc] \
        + [(x_yc, s.ground(x_yc))]
    deep = yc - 2.0 * s.height  # the wedge reaches below the ground; cut to the shoulders
    wedge_dx = s.zone_I_slope * (yc - deep)
    return {
        "foundation": [(xl, yb), (xr, yb), *ground],
        "yellow_clay": yc_top + [(x, y - t) for x, y in reversed(yc_top)],
        "core": s.core_outline(),
        "berm": [(x_berm_in, s.berm_top), (x_berm_in - s.berm_width, s.berm_top),
                 (s.berm_toe, yk), (xk, yk)],
        "zone_I": [(-hw, yc), (-hw - wedge_dx, deep), (hw + wedge_dx, deep), (hw, yc)],
        "zone_II": [(-hw, yc), (xk, yk), (x_boot, yf), (s.downstream_toe, yf), (hw, yc)],
    }


def build(gmsh, size: float = 6.0, far_size: float | None = None,
          layer_size: float | None = None, cells: str = "quadrilateral", **dimensions) -> None:
    """Create the Ch. 725 section in the current gmsh model and mesh it.

    Args:
        size: element size [m] in the embankment and the top of the foundation (6 m: about
            1 000 quadrilaterals, as the thesis's mesh; 12 m: a coarse test mesh).
        far_size: element size at the far boundaries [m] (default 4 x size).
        layer_size: element size in the yellow clay [m] (default: its thickness, at most
            ``size``).
        cells: "quadrilateral" (default) or "triangle".
        dimensions: overrides of :class:`Section` fields.
    """
    s = Section(**dimensions)
    if cells not in ("quadrilateral", "triangle"):
        raise ValueError(f"cells must be 'triangle' or 'quadrilateral', not {cells!r}")
    fine = size
    far = 4.0 * size if far_size is None else far_size
    layer = min(size, s.yellow_clay_thickness if layer_size is None else layer_size)
    occ = gmsh.model.occ
    regions = {name: [(2, _polygon(occ, points))] for name, points in _outlines(s).items()}
    core = regions["core"]
    regions["foundation"], _ = occ.cut(regions["foundation"], core + regions["yellow_clay"],
                                       removeTool=False)
    regions["zone_II"], _ = occ.cut(regions["zone_II"], core, removeTool=False)
    regions["zone_I"], _ = occ.intersect(regions["zone_I"], regions["zone_II"],
                                         removeTool=False)
    regions["zone_II"], _ = occ.cut(regions["zone_II"], regions["zone_I"], removeTool=False)
    # lift tops: horizontal bands cut every region into lifts
    tops = lift_tops(s.crest_level, s.berm_top, s.lifts, s.parts_above, s.part_height)
    xl, xr, yb = s.extent
    bands = [(2, occ.addRectangle(xl - 1.0, tops[k], 0, xr - xl + 2.0, tops[k + 1] - tops[k]))
             for k in range(len(tops) - 1)]
    inputs = [(name, dimtag) for name, dimtags in regions.items() for dimtag in dimtags]
    _, children = occ.fragment([d for _, d in inputs], bands)
    groups: dict[str, list[int]] = {name: [] for name in _NAMES}
    for (name, _), kids in zip(inputs, children):
        groups[name].extend(tag for _, tag in kids)
    kept = {tag for tags in groups.values() for tag in tags}
    occ.remove([(2, tag) for kids in children for _, tag in kids if tag not in kept],
               recursive=True)
    occ.synchronize()

    # boundaries: by position; "surface" is every other curve on one surface only
    eps = 1e-6 * (xr - xl)
    boundary: dict[str, list[int]] = {"base": [], "left": [], "right": [], "crest": [],
                                      "surface": []}
    for _, curve in gmsh.model.getEntities(1):
        x0, y0, _, x1, y1, _ = gmsh.model.getBoundingBox(1, curve)
        if abs(y0 - yb) < eps and abs(y1 - yb) < eps:
            boundary["base"].append(curve)
        elif abs(x0 - xl) < eps and abs(x1 - xl) < eps:
            boundary["left"].append(curve)
        elif abs(x0 - xr) < eps and abs(x1 - xr) < eps:
            boundary["right"].append(curve)
        elif len(gmsh.model.getAdjacencies(1, curve)[0]) == 1:
            crest = abs(y0 - s.crest_level) < eps and abs(y1 - s.crest_level) < eps
            boundary["crest" if crest else "surface"].append(curve)

    # element size: `size` over the embankment and the top of the foundation, growing to
    # `far` at the model's far boundaries, at most the yellow-clay thickness in that layer
    field = gmsh.model.mesh.field
    box = field.add("Box")
    field.setNumber(box, "VIn", fine)
    field.setNumber(box, "VOut", far)
    field.setNumber(box, "XMin", s.berm_toe - fine)
    field.setNumber(box, "XMax", s.downstream_toe + fine)
    field.setNumber(box, "YMin", s.foundation_level - s.trench_depth - fine)
    field.setNumber(box, "YMax", s.crest_level + 1.0)
    field.setNumber(box, "Thickness", 0.4 * max(s.margin, s.foundation_depth))
    sizes = [box]
    if layer < fine:
        layer_curves = sorted({abs(c) for surf in groups["yellow_clay"]
                               for _, c in gmsh.model.getBoundary([(2, surf)])})
        dist = field.add("Distance")
        field.setNumbers(dist, "CurvesList", layer_curves)
        field.setNumber(dist, "NumPointsPerCurve", 200)
        near = field.add("Threshold")  # `layer` in the layer, `fine` one `fine` from it
        field.setNumber(near, "InField", dist)
        field.setNumber(near, "SizeMin", layer)
        field.setNumber(near, "SizeMax", far)
        field.setNumber(near, "DistMin", 0.5 * layer)
        field.setNumber(near, "DistMax", 0.5 * layer + fine * (far - layer) / (fine - layer))
        sizes.append(near)
    smallest = field.add("Min")
    field.setNumbers(smallest, "FieldsList", sizes)
    field.setAsBackgroundMesh(smallest)
    gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
    for name in _NAMES:
        physical_group(gmsh, 2, sorted(groups[name]), name)
    for name, curves in boundary.items():
        physical_group(gmsh, 1, sorted(curves), name)
    if cells == "quadrilateral":
        quad_options(gmsh)
        # blossom leaves triangles in thin pieces (toes, lift tops); its full-quad variant
        # with an even number of segments on every curve does not, MeshAdapt gave the best
        # quadrilaterals (measured: smallest corner sine 0.32 at size 6 against 0.19)
        gmsh.option.setNumber("Mesh.Algorithm", 1)
        gmsh.option.setNumber("Mesh.RecombinationAlgorithm", 3)
        _even_curve_divisions(gmsh)
    gmsh.model.mesh.generate(2)


def _even_curve_divisions(gmsh) -> None:
    """Give every curve an even number of segments (as the size field meshes it, plus one
    where odd): full-quad recombination needs an even number of nodes around each surface."""
    mesh = gmsh.model.mesh
    mesh.generate(1)
    counts = {}
    for _, curve in gmsh.model.getEntities(1):
        nodes = mesh.getNodes(1, curve, includeBoundary=True)[0]
        segments = max(len(nodes) - 1, 1)
        counts[curve] = segments + segments % 2
    mesh.clear()
    for curve, segments in counts.items():
        mesh.setTransfiniteCurve(curve, segments + 1)
