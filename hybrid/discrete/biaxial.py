"""Plane-strain biaxial test of a packing of triangle grains: its bulk friction angle.

A packing of elastic grains (unstructured triangles, the cells of gmsh's default algorithm as
the granular column of R1 is meshed) bonded by interfaces without cohesion or tensile strength
that fail as soon as they open or slide, and that meet from then on by Coulomb contact at the
contact angle ``phi_c`` (bonds at the same angle), is much stronger in bulk than its contact
friction: angular grains interlock and a triangle cannot roll. DEM practice calibrates the
inter-particle (micro) friction so that the packing's bulk (macro) friction equals the
material's; :func:`biaxial_test` measures the bulk angle of a packing, :data:`CALIBRATION`
holds the measured curve and :func:`contact_friction` inverts it.

The test: a rectangular specimen ``cells_across`` grains wide and ``slenderness`` times as high,
between two rigid smooth platens (frictionless contact), without gravity. Its two sides carry a
constant pressure ``pressure``: a flexible membrane, p times the height of each bin of one
grain's height on the outermost grain node of the bin, horizontal and inward, renewed at
every check (:func:`_side_load`).
The grains start in the isotropic state -p (interfaces in pure compression: intact); the top
platen then moves down at a constant speed (the axial strain rate set by the inertial number
below), the bottom one is held. The collisions lose energy through the normal contact
damping, as in R1, and Cundall's local damping makes the test quasi-static, as DEM practice
does.

Measured at every check: the axial strain (platen travel over the initial height) and the
packing's mean stress, sum over the grains of sigma_e A_e (the grains carry all the stress of
a dry packing; the area it is divided by cancels in the ratio below), whose in-plane principal
stresses s1 >= s3 (compression positive) give the mobilised friction
sin(phi_mob) = (s1 - s3) / (s1 + s3). The peak angle is the largest phi_mob; the critical-state
angle the mean of phi_mob over the axial strains ``critical_window``, when the specimen
has parted along a shear band and its two blocks slide on it at a steady mobilised angle
(the residual, critical-state friction of the band). Quasi-static: the inertial number
I = rate x d x sqrt(rho / p) (d the grain size) sets the rate; :data:`CALIBRATION` was
measured at I = 1e-3, and at half that rate the critical angles at phi_c = 10 deg of the
first two packings moved by 0.03 and 0.14 deg.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from hybrid.discrete import ties
from hybrid.discrete.builders import rectangle_mesh
from hybrid.discrete.solver import ExplicitSolver, RunOptions
from hybrid.discrete.state import DiscreteState, from_mesh
from hybrid.materials import Bond, Contact, Material

__all__ = ["BiaxialResult", "CALIBRATION", "CALIBRATION_CHECK", "CALIBRATION_COMMAND",
           "CHECK_PACKINGS", "Calibration", "biaxial_test",
           "bulk_friction", "contact_friction", "specimen"]

#: The command that measures :data:`CALIBRATION` (and prints it as it is written below).
CALIBRATION_COMMAND = "python -m hybrid.discrete.biaxial"

#: (contact angle [deg], critical-state bulk angle [deg] of each packing) rows.
Calibration = tuple[tuple[float, tuple[float, ...]], ...]

#: The measured curve: (contact angle phi_c [deg], critical-state bulk angle [deg] of each
#: packing of :data:`CALIBRATION_PACKINGS`), the output of :data:`CALIBRATION_COMMAND` at the
#: defaults of :func:`biaxial_test` (pressure 1 kPa, I = 1e-3, local damping 0.7, axial
#: strain 15 to 25 %; grains of R1: E = 840 kPa, nu = 0.3, 2.65 t/m3, contact damping 0.3,
#: k_t = k_n / 10), one thread. The packings differ by 7 to 9 deg at every angle, with no
#: trend in the specimen's width (10, 14, 20 grains across weaker in turn, 28 the strongest,
#: its window the noisiest): the curve is the mean, known to about +- 2 deg (the standard
#: error of four packings), which is +- 2 deg in the contact angle; one packing alone may
#: lie 4 deg either side of it, or further (:data:`CALIBRATION_CHECK`).
CALIBRATION: Calibration = (
    (10, (20.25, 16.99, 14.78, 22.16)),
    (15, (26.11, 22.5, 19.64, 28.89)),
    (19.8, (29.14, 25.83, 24.01, 31.52)),
)

#: The packings of the calibration: grains across the specimen (each its own unstructured
#: mesh, so its own random packing).
CALIBRATION_PACKINGS = (10, 14, 20, 28)

#: Three more packings, measured as :data:`CALIBRATION` (``python -m hybrid.discrete.biaxial
#: --across 12 16 24``): a check of the curve's mean, not part of it (docs/hybrid.md).
CALIBRATION_CHECK: Calibration = (
    (10, (26.53, 16.25, 14.79)),
    (15, (22.97, 21.15, 19.7)),
    (19.8, (38.4, 25.94, 22.9)),
)
#: The packings of :data:`CALIBRATION_CHECK`: grains across.
CHECK_PACKINGS = (12, 16, 24)
#: Contact angles of the calibration [deg].
CALIBRATION_ANGLES = (10.0, 15.0, 19.8)


def _specimen_builder(gmsh, width: float, height: float, size: float) -> None:
    """A ``width`` x ``height`` rectangle of unstructured triangles of side ``size`` (gmsh)."""
    from hybrid.geometry import physical_group

    geo = gmsh.model.geo
    pts = [geo.addPoint(x, y, 0) for x, y in ((0, 0), (width, 0), (width, height),
                                              (0, height))]
    lines = [geo.addLine(pts[i], pts[(i + 1) % 4]) for i in range(4)]
    for ln, span in zip(lines, (width, height, width, height)):
        geo.mesh.setTransfiniteCurve(ln, max(int(round(span / size)), 1) + 1)
    surf = geo.addPlaneSurface([geo.addCurveLoop(lines)])
    geo.synchronize()
    physical_group(gmsh, 2, [surf], "specimen")
    physical_group(gmsh, 1, [lines[3]], "left")
    gmsh.model.mesh.generate(2)


def specimen(phi_c: float, *, cells_across: int = 10, slenderness: float = 2.0,
             size: float = 0.01, E: float = 840.0, nu: float = 0.3, density: float = 2.65,
             contact_damping: float = 0.3) -> tuple[DiscreteState, np.ndarray]:
    """The packing between its platens, stress-free; and the (n_elements,) specimen mask.

    Grains: unstructured triangles of side ``size`` [m] filling ``cells_across`` x
    ``slenderness`` grains; interfaces of cohesion 0, tensile strength 0 and angle ``phi_c``,
    contact at ``phi_c`` with k_n = 10 E / size, k_t = k_n / 10, normal damping ratio
    ``contact_damping`` (R1's grains). Platens: one row of held triangles above and below,
    twice the specimen's width, frictionless.
    """
    from hybrid.geometry import build_mesh

    width = cells_across * size
    height = slenderness * width
    mesh = build_mesh(_specimen_builder, width=width, height=height, size=size)
    pts, cells = mesh.cell_vertices()
    kn = 10.0 * E / size
    grains = Material(name="grains", E=E, nu=nu, density=density, plastic=False,
                      bond=Bond(cohesion=0.0, phi=phi_c, tensile_strength=0.0),
                      contact=Contact(phi=phi_c, damping=contact_damping, normal_stiffness=kn,
                                      shear_stiffness=kn / 10.0))
    platen = Material(name="platen", E=E, nu=nu, density=density, plastic=False,
                      contact=Contact(phi=0.0, damping=contact_damping, normal_stiffness=kn,
                                      shear_stiffness=kn / 10.0))
    parts_p: list[np.ndarray] = [np.asarray(pts)[:, :2]]
    parts_c: list[np.ndarray] = [np.asarray(cells)]
    mats: list[np.ndarray] = [np.zeros(len(cells), dtype=np.int32)]
    n_pl = 2 * cells_across
    for y0 in (-size, height):
        p, c = rectangle_mesh(2.0 * width, size, n_pl, 1, "T3", origin=(-0.5 * width, y0))
        parts_c.append(c + sum(len(q) for q in parts_p))
        parts_p.append(p)
        mats.append(np.ones(len(c), dtype=np.int32))
    st = from_mesh(np.concatenate(parts_p), np.concatenate(parts_c), np.concatenate(mats),
                   [grains, platen], gravity=(0.0, 0.0))
    grain = st.element_material == 0
    ties.limit_splitting(st, grain)
    st.fix(np.unique(st.element_nodes[~grain]))
    return st, grain


def _side_load(st: DiscreteState, nodes: np.ndarray, bottom: float, top: float, bin_h: float,
               pressure: float) -> None:
    """Set the external force: ``pressure`` on the specimen's two sides, a flexible membrane.

    The height between the platens (``bottom`` to ``top`` [m]) is cut into bins of about
    ``bin_h``; in each bin the outermost grain node on either side (among ``nodes``) carries
    p times the bin's height, horizontal and inward. The membrane follows the specimen as it
    bulges, and a grain squeezed out between its neighbours becomes the outermost and is
    pushed back: the pressure always acts on the current outline.
    """
    st.external_force[:] = 0.0
    n_bins = max(int(round((top - bottom) / bin_h)), 1)
    h = (top - bottom) / n_bins
    x, y = st.x[nodes, 0], st.x[nodes, 1]
    k = np.clip(((y - bottom) / h).astype(np.int64), 0, n_bins - 1)
    for sign, key in ((1.0, x), (-1.0, -x)):  # left side pushed to +x, right side to -x
        order = np.lexsort((key, k))
        first = order[np.r_[True, k[order][1:] != k[order][:-1]]]
        st.external_force[nodes[first], 0] += sign * pressure * h


def _mobilised(st: DiscreteState, grain: np.ndarray) -> tuple[float, float]:
    """(phi_mob [deg], mean pressure (s1 + s3) / 2 over the grains' area [kPa])."""
    en = st.element_nodes[grain]
    p = st.x[en]
    area = 0.5 * np.abs(np.sum(p[:, :, 0] * np.roll(p[:, :, 1], -1, axis=1)
                               - np.roll(p[:, :, 0], -1, axis=1) * p[:, :, 1], axis=1))
    s = st.stress[grain].mean(axis=1)  # (n, 4): xx, yy, zz, xy
    sxx, syy, sxy = (-(s[:, i] * area).sum() for i in (0, 1, 3))
    centre, radius = 0.5 * (sxx + syy), math.hypot(0.5 * (sxx - syy), sxy)
    phi = math.degrees(math.asin(min(radius / centre, 1.0))) if centre > 0 else float("nan")
    return phi, centre / area.sum()


@dataclass
class BiaxialResult:
    """What :func:`biaxial_test` measured.

    Attributes:
        phi_c: contact (and bond) friction angle [deg].
        peak: largest mobilised friction angle [deg].
        critical: mean mobilised angle over the critical window [deg].
        critical_spread: standard deviation of the mobilised angle there [deg].
        inertial_number: rate x grain size x sqrt(density / pressure) [-].
        strain: axial strain at each check [-].
        phi_mob: mobilised friction angle at each check [deg].
        mean_pressure: (s1 + s3) / 2 over the grains' area at each check [kPa].
        lateral_strain: width change over the initial width at each check (outermost
            grain nodes; a grain squeezed out counts) [-].
        elements: grains of the specimen.
        wall_time_s: seconds of the run.
        state: the specimen at the end (figures).
        grain: (n_elements,) True for the specimen's grains (the rest: platens).
    """

    phi_c: float
    peak: float
    critical: float
    critical_spread: float
    inertial_number: float
    strain: np.ndarray = field(repr=False)
    phi_mob: np.ndarray = field(repr=False)
    mean_pressure: np.ndarray = field(repr=False)
    lateral_strain: np.ndarray = field(repr=False)
    elements: int = 0
    wall_time_s: float = 0.0
    state: DiscreteState | None = field(default=None, repr=False)
    grain: np.ndarray | None = field(default=None, repr=False)


def biaxial_test(phi_c: float, *, cells_across: int = 10, slenderness: float = 2.0,
                 pressure: float = 1.0, inertial_number: float = 1e-3,
                 final_strain: float = 0.25, critical_window: tuple[float, float] = (0.15, 0.25),
                 size: float = 0.01, E: float = 840.0, nu: float = 0.3, density: float = 2.65,
                 contact_damping: float = 0.3, local_damping: float = 0.7,
                 check_every: int = 50) -> BiaxialResult:
    """Compress the packing of :func:`specimen` at constant lateral pressure; its friction.

    Args:
        phi_c: contact and bond friction angle [deg].
        cells_across: grains across the specimen (each count its own packing) [-].
        slenderness: height over width [-].
        pressure: lateral (and initial isotropic) pressure [kPa].
        inertial_number: I = rate x size x sqrt(density / pressure), which sets the axial
            strain rate (quasi-static below about 1e-3) [-].
        final_strain: axial strain at the end [-].
        critical_window: axial strains over which the critical-state angle is averaged [-].
        size: grain size [m] (triangle side; k_n = 10 E / size).
        E: Young's modulus of the grains [kPa].
        nu: Poisson's ratio of the grains [-].
        density: density of the grains [t/m3].
        contact_damping: normal contact damping ratio [-].
        local_damping: Cundall's local damping d [-] (``RunOptions.local_damping``), the
            DEM practice of quasi-static tests (0.7 is PFC's default): it keeps a grain
            squeezed out of the specimen from flying off. At 0.3 instead, the first packing's
            critical angle at phi_c = 10 deg was 2.0 deg lower (18.2 against 20.3), less
            than the packings differ (7.4 deg there).
        check_every: steps between checks (the side load is renewed at each).

    Returns:
        The peak and critical-state angles with the curves.
    """
    if not 0.0 < critical_window[0] < critical_window[1] <= final_strain:
        raise ValueError(f"critical_window = {critical_window}: need 0 < start < end <= "
                         f"final_strain = {final_strain}")
    st, grain = specimen(phi_c, cells_across=cells_across, slenderness=slenderness, size=size,
                         E=E, nu=nu, density=density, contact_damping=contact_damping)
    width = cells_across * size
    height = slenderness * width
    rate = inertial_number / (size * math.sqrt(density / pressure))
    st.stress[grain, :, 0] = -pressure
    st.stress[grain, :, 1] = -pressure
    st.stress[grain, :, 2] = -2.0 * nu * pressure
    st.primed = False
    nodes = np.unique(st.element_nodes[grain])
    bin_h = size
    _side_load(st, nodes, 0.0, height, bin_h, pressure)
    top = np.unique(st.element_nodes[~grain & (st.element_centroids()[:, 1] > height)])
    st.fix(top, velocity=(0.0, -rate * height))
    rec: dict[str, list[float]] = {"strain": [], "phi": [], "p": [], "lateral": []}

    def check(state: DiscreteState) -> None:
        _side_load(state, nodes, 0.0, height * (1.0 - rate * state.time), bin_h, pressure)
        phi, p = _mobilised(state, grain)
        rec["strain"].append(rate * state.time)
        rec["phi"].append(phi)
        rec["p"].append(p)
        xs = state.x[nodes, 0]
        rec["lateral"].append((xs.max() - xs.min()) / width - 1.0)

    margin = 10.0 * width
    options = RunOptions(split_every=10, contact=True, local_damping=local_damping,
                         contact_bounds=(-margin, -margin, width + margin, height + margin))
    with ExplicitSolver(st, options) as solver:
        res = solver.run(until_time=final_strain / rate, check_every=check_every,
                         on_check=check)
    eps, phi = np.asarray(rec["strain"]), np.asarray(rec["phi"])
    lat = np.asarray(rec["lateral"])
    lo, hi = critical_window
    win = (eps >= lo) & (eps <= hi)
    return BiaxialResult(
        phi_c=phi_c, peak=float(np.nanmax(phi)), critical=float(np.nanmean(phi[win])),
        critical_spread=float(np.nanstd(phi[win])), inertial_number=inertial_number,
        strain=eps, phi_mob=phi, mean_pressure=np.asarray(rec["p"]), lateral_strain=lat,
        elements=int(grain.sum()), wall_time_s=res.wall_time, state=st, grain=grain)


def bulk_friction(phi_c: float, calibration: Calibration = CALIBRATION) -> float:
    """Critical-state bulk friction angle [deg] of the packing at contact angle ``phi_c``.

    Linear interpolation in ``calibration`` (:data:`CALIBRATION`: the mean over its
    packings); outside the measured angles a ValueError.
    """
    c, b = _curve(calibration)
    if not c[0] <= phi_c <= c[-1]:
        raise ValueError(f"phi_c = {phi_c:g} deg is outside the calibrated contact angles "
                         f"{c[0]:g}..{c[-1]:g} deg ({CALIBRATION_COMMAND})")
    return float(np.interp(phi_c, c, b))


def contact_friction(phi_bulk: float, calibration: Calibration = CALIBRATION) -> float:
    """Contact angle [deg] of a triangle-grain packing whose bulk friction is ``phi_bulk``.

    The inverse of :func:`bulk_friction`: linear interpolation in ``calibration``
    (:data:`CALIBRATION`: the critical-state bulk angle, mean over its packings, rises with
    the contact angle). A
    bulk angle outside the measured range is refused (ValueError): the packing of
    frictionless-contact triangles is already that strong, or stronger ones were not
    measured.
    """
    c, b = _curve(calibration)
    if np.any(np.diff(b) <= 0):
        raise ValueError("the calibration's bulk angles do not rise with the contact angle: "
                         "cannot invert it")
    if not b[0] <= phi_bulk <= b[-1]:
        raise ValueError(f"phi_bulk = {phi_bulk:g} deg is outside the calibrated bulk angles "
                         f"{b[0]:.3g}..{b[-1]:.3g} deg (contact angles {c[0]:g}..{c[-1]:g} deg; "
                         f"{CALIBRATION_COMMAND}); a case can give the contact angle "
                         "itself instead (granular_collapse: --set contact_phi=...)")
    return float(np.interp(phi_bulk, b, c))


def _curve(calibration: Calibration) -> tuple[np.ndarray, np.ndarray]:
    if not calibration:
        raise ValueError(f"no calibration: run {CALIBRATION_COMMAND}")
    c = np.array([row[0] for row in calibration])
    b = np.array([float(np.mean(row[1])) for row in calibration])
    return c, b


def main(argv: list[str] | None = None) -> None:
    """Measure :data:`CALIBRATION` and print it (``--angles``, ``--across``: other runs)."""
    import argparse

    parser = argparse.ArgumentParser(prog=CALIBRATION_COMMAND, description=__doc__.split(
        "\n")[0])
    parser.add_argument("--angles", type=float, nargs="+", default=CALIBRATION_ANGLES,
                        help="contact angles [deg]")
    parser.add_argument("--across", type=int, nargs="+", default=CALIBRATION_PACKINGS,
                        help="grains across the specimen, one packing each")
    args = parser.parse_args(argv)
    rows = []
    for phi_c in args.angles:
        results = []
        for n in args.across:
            r = biaxial_test(phi_c, cells_across=n)
            results.append(r)
            print(f"# phi_c {phi_c:g}: {n} across ({r.elements} grains): peak {r.peak:.2f}, "
                  f"critical {r.critical:.2f} +- {r.critical_spread:.2f} deg, "
                  f"{r.wall_time_s:.0f} s", flush=True)
        rows.append((phi_c, tuple(round(r.critical, 2) for r in results)))
    print("CALIBRATION = (")
    for phi_c, bulk in rows:
        print(f"    ({phi_c:g}, {bulk}),")
    print(")")


if __name__ == "__main__":
    main()
