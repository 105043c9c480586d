"""gmsh -> dolfinx: named groups, both cell types, clear errors for bad meshes."""

from pathlib import Path

import numpy as np
import pytest

from hybrid.geometry import (
    GeometryError,
    build_mesh,
    load_builder,
    load_mesh_script,
    physical_group,
    read_msh,
)
from hybrid.materials import Material
from hybrid.model import Fixed, Model, ModelError, Pressure


def _two_squares(gmsh, recombine_first=False, group_second=True, empty_curve=False,
                 duplicate=False):
    geo = gmsh.model.geo
    pts = [geo.addPoint(x, y, 0, 0.25) for x, y in ((0, 0), (1, 0), (2, 0), (2, 1), (1, 1),
                                                     (0, 1))]
    lines = [geo.addLine(pts[i], pts[(i + 1) % 6]) for i in range(6)]
    mid = geo.addLine(pts[1], pts[4])
    left = geo.addPlaneSurface([geo.addCurveLoop([lines[0], mid, lines[4], lines[5]])])
    right = geo.addPlaneSurface([geo.addCurveLoop([lines[1], lines[2], lines[3], -mid])])
    lone = geo.addLine(geo.addPoint(5, 0, 0), geo.addPoint(6, 0, 0))
    if recombine_first:
        geo.mesh.setRecombine(2, left)
    geo.synchronize()
    physical_group(gmsh, 2, [left], "left_soil")
    if group_second:
        physical_group(gmsh, 2, [right], "right_soil")
    if duplicate:
        physical_group(gmsh, 2, [right], "again")
    physical_group(gmsh, 1, [lines[0], lines[1]], "base")
    if empty_curve:
        physical_group(gmsh, 1, [lone], "lonely")
    gmsh.model.mesh.generate(2)
    if empty_curve:
        gmsh.model.mesh.clear([(1, lone)])


@pytest.mark.parametrize("cells", ["triangle", "quadrilateral"])
def test_named_groups_and_cell_types(builder, cells):
    mesh = build_mesh(builder("block"), width=2.0, height=1.0, nx=4, ny=2, cells=cells)
    assert mesh.cell_type == cells
    assert set(mesh.cell_groups) == {"soil"}
    assert set(mesh.facet_groups) == {"base", "top", "left", "right"}
    # structured 4 x 2 grid: 8 quads or 16 triangles, exactly
    assert mesh.comm.allreduce(mesh.num_owned_cells) == (8 if cells == "quadrilateral" else 16)
    x, nodes = mesh.cell_vertices()
    polys = x[nodes]
    # counter-clockwise cells with the exact total area 2 m2
    area = 0.5 * np.sum(polys[:, :, 0] * np.roll(polys[:, :, 1], -1, axis=1)
                        - np.roll(polys[:, :, 0], -1, axis=1) * polys[:, :, 1], axis=1)
    assert np.all(area > 0)
    assert mesh.comm.allreduce(area.sum()) == pytest.approx(2.0, rel=1e-12)
    # the named facets of the base lie on y = 0
    assert len(mesh.facets("base")) == 4


def test_two_materials_by_name():
    mesh = build_mesh(_two_squares)
    assert set(mesh.cell_groups) == {"left_soil", "right_soil"}
    clay, sand = Material(name="clay", E=1e4, nu=0.3), Material(name="sand", E=5e4, nu=0.25)
    model = Model(mesh, {"left_soil": clay, "right_soil": sand}, supports=[Fixed("base")])
    E = model.cell_property("E")
    x, nodes = mesh.cell_vertices()
    centroid_x = x[nodes][:, :, 0].mean(axis=1)
    assert np.all(E[centroid_x < 1.0] == 1e4) and np.all(E[centroid_x > 1.0] == 5e4)


def test_mixed_cell_types_refused():
    with pytest.raises(GeometryError, match="mixes cell types"):
        build_mesh(_two_squares, recombine_first=True)


def test_cell_without_material_refused():
    with pytest.raises(GeometryError, match="have no material"):
        build_mesh(_two_squares, group_second=False)


def test_cell_in_two_groups_refused():
    with pytest.raises(GeometryError, match="more than one material group"):
        build_mesh(_two_squares, duplicate=True)


def test_empty_group_refused():
    with pytest.raises(GeometryError, match="'lonely' .* is empty"):
        build_mesh(_two_squares, empty_curve=True)


def test_unknown_names_refused(builder):
    mesh = build_mesh(builder("block"))
    soil = Material(name="soil", E=1e4, nu=0.3)
    with pytest.raises(ModelError, match="unknown boundary .*'bottom'.*base, left, right, top"):
        Model(mesh, {"soil": soil}, supports=[Fixed("bottom")])
    with pytest.raises(ModelError, match="unknown cell group 'clay'"):
        Model(mesh, {"soil": soil, "clay": soil})
    with pytest.raises(ModelError, match="have no material"):
        Model(mesh, {})
    with pytest.raises(ModelError, match="Pressure: unknown boundary"):
        Model(mesh, {"soil": soil}, loads=[Pressure("roof", 1.0)])
    with pytest.raises(GeometryError, match="unknown cell"):
        mesh.cells("rock")


def test_read_msh_file(tmp_path):
    import gmsh

    path = tmp_path / "two.msh"
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    _two_squares(gmsh)
    gmsh.write(str(path))
    gmsh.finalize()
    mesh = read_msh(path)
    assert set(mesh.cell_groups) == {"left_soil", "right_soil"}
    assert set(mesh.facet_groups) == {"base"}
    with pytest.raises(GeometryError, match="does not exist"):
        read_msh(tmp_path / "missing.msh")


def test_load_mesh_script(tmp_path):
    """A gmsh script loads whole (its builder and what else it defines) or names the file."""
    meshes = Path(__file__).resolve().parent.parent / "meshes"
    section = load_mesh_script(meshes / "carsington.py")
    assert callable(section.build) and section.Section().lifts == 5
    assert load_builder(meshes / "carsington.py").__name__ == "build"
    with pytest.raises(GeometryError, match="not found"):
        load_mesh_script(tmp_path / "missing.py")
    (tmp_path / "empty.py").write_text("")
    with pytest.raises(GeometryError, match="defines no function 'build'"):
        load_builder(tmp_path / "empty.py")


@pytest.mark.parametrize("cells", ["triangle", "quadrilateral"])
def test_structured_footing_mesh(builder, cells):
    """The footing's structured option: two transfinite blocks with the same named groups,
    cells ``fine`` wide at the footing edge and growing geometrically to about ``coarse``."""
    mesh = build_mesh(builder("footing"), width=4.8, depth=3.0, half_footing=0.6, fine=0.08,
                      coarse=0.4, cells=cells, structured=True)
    assert mesh.cell_type == cells
    assert set(mesh.cell_groups) == {"soil"}
    assert set(mesh.facet_groups) == {"footing", "surface", "right", "base", "symmetry"}
    x, nodes = mesh.cell_vertices()
    polys = x[nodes]
    area = 0.5 * np.sum(polys[:, :, 0] * np.roll(polys[:, :, 1], -1, axis=1)
                        - np.roll(polys[:, :, 0], -1, axis=1) * polys[:, :, 1], axis=1)
    assert np.all(area > 0)
    assert mesh.comm.allreduce(area.sum()) == pytest.approx(4.8 * 3.0, rel=1e-12)
    # the cell at the footing edge, below the surface, is fine x fine; the corner far away
    # about coarse x coarse (a quadrilateral, or two triangles)
    per_quad = 1 if cells == "quadrilateral" else 2
    at_edge = np.all(np.abs(polys - [0.6, 0.0]).max(axis=1) < 0.081, axis=1)
    assert area[at_edge].sum() == pytest.approx(2 * 0.08 ** 2, rel=0.05)
    assert at_edge.sum() == 2 * per_quad
    far = np.all(polys.min(axis=1) > [4.3, -2.5], axis=1) & np.all(
        polys.max(axis=1) < [4.8 + 1e-9, -2.5 + 0.6], axis=1)
    assert np.all(np.sqrt(area[far] * per_quad) > 0.3)
    # the grading fills its length from the first size to about the last
    grading = load_mesh_script(Path(__file__).resolve().parent.parent / "meshes"
                               / "footing.py").grading
    n, r = grading(4.2, 0.08, 0.4)
    sizes = 0.08 * r ** np.arange(n)
    assert sizes.sum() == pytest.approx(4.2, rel=1e-9)
    assert sizes[-1] == pytest.approx(0.4, rel=0.1)
    assert grading(0.3, 0.08, 0.4) == (4, 1.0)  # shorter than the last size: uniform


@pytest.mark.parametrize("cells", ["triangle", "quadrilateral"])
@pytest.mark.parametrize("size", [1.0, 0.5])
def test_unstructured_wall_mesh(builder, cells, size):
    """The wall's unstructured option: the same named groups and regions as the structured
    grid, cells all of one type (full-quad recombination leaves no triangle in the 1 m ground
    layer), none inverted, quadrilateral corners no sharper than 30 deg (sine 0.5)."""
    mesh = build_mesh(builder("wall"), size=size, cells=cells, structured=False)
    assert mesh.cell_type == cells  # build_mesh refuses a mesh of mixed cell types
    assert set(mesh.cell_groups) == {"backfill", "ground"}
    assert set(mesh.facet_groups) == {"wall", "base", "right", "left", "surface",
                                      "backfill_base"}
    x, nodes = mesh.cell_vertices()
    polys = x[nodes]
    area = 0.5 * np.sum(polys[:, :, 0] * np.roll(polys[:, :, 1], -1, axis=1)
                        - np.roll(polys[:, :, 0], -1, axis=1) * polys[:, :, 1], axis=1)
    assert np.all(area > 0)
    assert area[mesh.cells("backfill")].sum() == pytest.approx(20.0 * 10.0, rel=1e-12)
    assert area[mesh.cells("ground")].sum() == pytest.approx(40.0 * 1.0, rel=1e-12)
    # not the structured grid: its cells do not all have the structured cells' area
    per_cell = size ** 2 / (1 if cells == "quadrilateral" else 2)
    assert not np.allclose(area, per_cell, rtol=1e-6)
    if cells == "quadrilateral":
        e_in = polys - np.roll(polys, 1, axis=1)
        e_out = np.roll(polys, -1, axis=1) - polys
        sine = (e_in[..., 0] * e_out[..., 1] - e_in[..., 1] * e_out[..., 0]) / (
            np.linalg.norm(e_in, axis=2) * np.linalg.norm(e_out, axis=2))
        assert sine.min() > 0.5
