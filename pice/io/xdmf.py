"""XDMF 3 description of a run file, so ParaView (and meshio, VisIt) open the HDF5 run directly.

``write_xdmf("runs/x.h5")`` writes ``runs/x.xdmf`` beside it; the heavy data stay in the run file
and are referenced by relative path. The domain holds two temporal collections with one grid per
snapshot and its ``Time``:

* ``bonds``: the intact bonds as a ``Polyline`` topology on the snapshot's positions;
* ``ice`` (last, so single-collection readers such as meshio's ``TimeSeriesReader`` pick it): the
  particles as a ``Polyvertex`` topology with the node attributes radius, velocity,
  angular_velocity, kind and gid.

Connectivity must be point indices. Snapshots are sorted by gid, so when the gids are 0..n-1 (all
runs so far) the ``gid`` and ``bonds`` datasets are referenced as they are and nothing is added;
otherwise the run-file writer stores ``point_index`` and ``bond_index``
(``point_index_arrays``) and those are referenced.
"""

from __future__ import annotations

import logging
import os
import pathlib
import xml.etree.ElementTree as ET

import h5py
import numpy as np

from .errors import OutputError
from .run_reader import open_run

# (dataset, attribute name, XDMF AttributeType) on the particles
_ATTRIBUTES = (("radius", "radius", "Scalar"), ("v", "velocity", "Vector"),
               ("w", "angular_velocity", "Vector"), ("kind", "kind", "Scalar"), ("gid", "gid", "Scalar"),
               ("crush_depth", "crush_depth", "Scalar"))



def point_index_arrays(gid: np.ndarray, bonds: np.ndarray) -> dict:
    """Connectivity by point index for readers that cannot follow gids (XDMF, see io/xdmf.py).

    ``gid`` is a snapshot's sorted gid array and ``bonds`` its (m,2) gid pairs. When the gids are
    0..n-1 (every run so far) they are their own indices and nothing extra is stored: {}. Otherwise
    ``point_index`` (0..n-1) and ``bond_index`` (bonds as indices into the snapshot's arrays).
    """
    n = len(gid)
    if n == 0 or (gid[0] == 0 and gid[-1] == n - 1):  # sorted and unique, so exactly 0..n-1
        return {}
    return {"point_index": np.arange(n, dtype=np.int64),
            "bond_index": np.searchsorted(gid, np.asarray(bonds, dtype=np.int64).reshape(-1, 2))}

def xdmf_path(run_path: str | os.PathLike) -> pathlib.Path:
    return pathlib.Path(run_path).with_suffix(".xdmf")


def _data_item(parent, h5name: str, ds: h5py.Dataset) -> ET.Element:
    kind = ds.dtype.kind
    if kind == "f":
        number = "Float"
    elif kind == "i":
        number = "Int"
    elif kind == "u":
        number = "UInt"
    else:
        raise OutputError(f"{ds.name}: dtype {ds.dtype} has no XDMF type")
    item = ET.SubElement(parent, "DataItem", Format="HDF", DataType=number, Precision=str(ds.dtype.itemsize),
                         Dimensions=" ".join(str(d) for d in ds.shape))
    item.text = f"{h5name}:{ds.name}"
    return item


def _connectivity(g: h5py.Group) -> tuple[h5py.Dataset, h5py.Dataset]:
    """(vertex connectivity, bond connectivity) datasets of one snapshot, as point indices."""
    if "point_index" in g and "bond_index" in g:
        return g["point_index"], g["bond_index"]
    gid = g["gid"]
    n = gid.shape[0]
    if n == 0 or (gid[0] == 0 and gid[n - 1] == n - 1):  # sorted by gid, so gid == index
        return gid, g["bonds"]
    raise OutputError(f"{g.file.filename}:{g.name}: gids are not 0..n-1 and the snapshot has no "
                      "point_index/bond_index datasets, so its bonds cannot be given as point indices")


def _grid(collection, name: str, g: h5py.Group, h5name: str, topology: str, conn: h5py.Dataset,
          attributes: bool) -> None:
    grid = ET.SubElement(collection, "Grid", Name=name, GridType="Uniform")
    ET.SubElement(grid, "Time", Value=repr(float(g.attrs["time"])))
    count = conn.shape[0]
    per = "1" if topology == "Polyvertex" else "2"
    topo = ET.SubElement(grid, "Topology", TopologyType=topology, NumberOfElements=str(count), NodesPerElement=per)
    if count:
        _data_item(topo, h5name, conn)
    else:  # an empty HDF5 dataset trips some readers: an empty inline array instead
        item = ET.SubElement(topo, "DataItem", Format="XML", DataType="Int", Precision="8",
                             Dimensions="0" if per == "1" else "0 2")
        item.text = ""
    geom = ET.SubElement(grid, "Geometry", GeometryType="XYZ")
    _data_item(geom, h5name, g["x"])
    if attributes:
        for ds, label, kind in _ATTRIBUTES:
            if ds not in g:  # a field the run file predates (crush_depth)
                continue
            attr = ET.SubElement(grid, "Attribute", Name=label, AttributeType=kind, Center="Node")
            _data_item(attr, h5name, g[ds])


def write_xdmf(run_h5_path: str | os.PathLike) -> pathlib.Path:
    """Write ``<run>.xdmf`` beside the run file (replacing an older one); return its path."""
    run = pathlib.Path(run_h5_path)
    out = xdmf_path(run)
    root = ET.Element("Xdmf", Version="3.0")
    domain = ET.SubElement(root, "Domain")
    bonds = ET.SubElement(domain, "Grid", Name="bonds", GridType="Collection", CollectionType="Temporal")
    ice = ET.SubElement(domain, "Grid", Name="ice", GridType="Collection", CollectionType="Temporal")
    try:
        with open_run(run) as f:  # RunFileError (exit status 5) for a missing or unreadable file
            for key in f.snapshots:
                g = f.snapshot(key)
                vertices, lines = _connectivity(g)
                _grid(bonds, f"bonds_{key}", g, run.name, "Polyline", lines, attributes=False)
                _grid(ice, f"ice_{key}", g, run.name, "Polyvertex", vertices, attributes=True)
    except OSError as exc:  # a dataset that cannot be read
        raise OutputError(f"{run}: cannot read the run file ({exc})") from None
    ET.indent(root)
    tmp = out.with_name(out.name + ".tmp")
    try:
        with open(tmp, "wb") as fh:
            fh.write(b'<?xml version="1.0" ?>\n<!DOCTYPE Xdmf SYSTEM "Xdmf.dtd" []>\n')
            fh.write(ET.tostring(root, encoding="utf-8"))
            fh.write(b"\n")
        os.replace(tmp, out)
    except OSError as exc:
        tmp.unlink(missing_ok=True)  # a full disk leaves no partial file behind
        raise OutputError(f"{out}: cannot write the XDMF file ({exc.strerror or exc})") from None
    return out


def write_xdmf_quietly(run_h5_path) -> pathlib.Path | None:
    """write_xdmf for the end of a run: a failure is logged as a warning, never raised."""
    try:
        return write_xdmf(run_h5_path)
    except Exception as exc:  # the run file itself is complete; the XDMF is a convenience
        logging.getLogger("pice").warning("no XDMF written beside %s: %s", run_h5_path, exc)
        return None
