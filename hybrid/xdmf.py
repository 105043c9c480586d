"""XDMF time series that open after every frame: the layout both phases write.

A series ``name.xdmf`` is an index over HDF5 files: the mesh in ``name.h5`` (``/mesh/geometry``
(n_points, 2) [m], ``/mesh/topology`` (n_cells, nodes per cell), ``/mesh/material`` (n_cells,)
index into the material names) and one file per frame in ``name_series/frame_NNNNN.h5``
(its fields by name). Each file and the index are written to a temporary file and renamed,
so the series opens in ParaView and in ``meshio.xdmf.TimeSeriesReader`` after every frame,
also after a kill. Plain numpy and h5py: no dolfinx, no numba.
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any
from xml.sax.saxutils import quoteattr

import numpy as np

__all__ = ["replace_file", "write_mesh", "write_frame", "write_index", "series_index"]


def replace_file(tmp: Path, path: Path) -> None:
    """Move a finished temporary file onto ``path`` (atomic on one file system)."""
    with open(tmp, "rb+") as f:
        os.fsync(f.fileno())
    os.replace(tmp, path)


def _temporary(path: Path) -> Path:
    return path.with_name(path.name + ".tmp")


def write_mesh(path: Path, geometry: np.ndarray, topology: np.ndarray, material: np.ndarray,
               material_names: Sequence[str], **attrs: Any) -> Path:
    """The mesh file of a series (``/mesh/...``, material names and ``attrs`` as attributes)."""
    import h5py

    tmp = _temporary(path)
    with h5py.File(tmp, "w") as f:
        g = f.create_group("mesh")
        g["geometry"] = np.asarray(geometry, dtype=float)
        g["topology"] = np.asarray(topology, dtype=np.int64)
        g["material"] = np.asarray(material, dtype=np.int32)
        g.attrs["material_names"] = ";".join(material_names)
        for key, value in attrs.items():
            g.attrs[key] = value
    replace_file(tmp, path)
    return path


def write_frame(path: Path, fields: Mapping[str, np.ndarray], **attrs: Any) -> Path:
    """One frame file: its fields by name, ``attrs`` (time, step, ...) as attributes.

    The temporary file is removed when the write fails (the error is raised).
    """
    import h5py

    tmp = _temporary(path)
    try:
        with h5py.File(tmp, "w") as f:
            for key, value in fields.items():
                f[key] = value
            for key, value in attrs.items():
                f.attrs[key] = value
        replace_file(tmp, path)
    except OSError:
        tmp.unlink(missing_ok=True)
        raise
    return path


def write_index(path: Path, text: str) -> Path:
    """Write the index text of a series (temporary file, renamed)."""
    tmp = _temporary(path)
    tmp.write_text(text)
    replace_file(tmp, path)
    return path


def series_index(*, mesh: str, cells: int, nodes_per_cell: int, points: int,
                 point_fields: Mapping[str, int], cell_fields: Sequence[str],
                 frames: Sequence[tuple[float, str]],
                 information: Mapping[str, str]) -> str:
    """The XDMF 3 text of a series: the mesh, then one grid per frame.

    ``mesh``: the mesh file's name (beside the index); ``point_fields``: name -> components
    (1 scalar, 2 vector); ``cell_fields``: scalar names; ``frames``: (time, frame file relative
    to the index); ``information``: name -> text, written as ``Information`` items of the
    domain (material names, what the time is). Every frame also has the mesh's ``material``.
    """
    def item(ref: str, dims: str, kind: str = "Float", precision: int = 8) -> str:
        return (f'<DataItem DataType="{kind}" Dimensions="{dims}" Format="HDF" '
                f'Precision="{precision}">{ref}</DataItem>')

    topo = {4: "Quadrilateral", 3: "Triangle"}[nodes_per_cell]
    ne, nen, nn = cells, nodes_per_cell, points
    lines = ['<?xml version="1.0"?>',
             '<Xdmf Version="3.0" xmlns:xi="http://www.w3.org/2001/XInclude">', "<Domain>"]
    lines += [f'<Information Name={quoteattr(k)} Value={quoteattr(v)}/>'
              for k, v in information.items()]
    lines += ['<Grid Name="mesh" GridType="Uniform">',
              f'<Topology TopologyType="{topo}" NumberOfElements="{ne}">'
              f'{item(f"{mesh}:/mesh/topology", f"{ne} {nen}", "Int")}</Topology>',
              f'<Geometry GeometryType="XY">{item(f"{mesh}:/mesh/geometry", f"{nn} 2")}'
              "</Geometry>", "</Grid>",
              '<Grid Name="series" GridType="Collection" CollectionType="Temporal">']
    include = ('<xi:include xpointer="xpointer(//Grid[@Name=&quot;mesh&quot;]/*[self::Topology '
               'or self::Geometry])"/>')
    for time, name in frames:
        lines += ["<Grid>", include, f'<Time Value="{time!r}"/>']
        lines += [f'<Attribute Name="{f}" AttributeType="{"Vector" if k > 1 else "Scalar"}" '
                  f'Center="Node">{item(f"{name}:/{f}", f"{nn} {k}" if k > 1 else str(nn))}'
                  "</Attribute>" for f, k in point_fields.items()]
        lines += [f'<Attribute Name="{f}" AttributeType="Scalar" Center="Cell">'
                  f'{item(f"{name}:/{f}", str(ne))}</Attribute>' for f in cell_fields]
        lines += ['<Attribute Name="material" AttributeType="Scalar" Center="Cell">'
                  f'{item(f"{mesh}:/mesh/material", str(ne), "Int", 4)}</Attribute>',
                  "</Grid>"]
    lines += ["</Grid>", "</Domain>", "</Xdmf>", ""]
    return "\n".join(lines)
