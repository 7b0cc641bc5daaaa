#!/usr/bin/env python3
"""Check an XDMF 3 file written by rebond (fields.xmf) against its HDF5 heavy data.

Usage: check_xdmf.py FILE.xmf [--grids N]

Checks that the XML parses, that it holds a temporal collection of uniform grids each with a
Time, a Mixed topology and an XYZ geometry, and that every HDF DataItem points to an existing
dataset of the declared dimensions, number type and precision (a HyperSlab DataItem: its
selection inside its source dataset). The Mixed topology array is
walked to check its element count and node ids. Attribute sizes are checked against the grid
(Node: nnode rows, Cell: nelem rows; Vector: 3 components, Scalar: 1). rebond is 2-D, so a
nodal Vector must have a zero z component (a 3D mesh, z not all zero: any) (ParaView's "Warp By Vector" then stays in the
plane); the rotational part lives in a nodal Scalar named after its vector (displacement ->
rotation, velocity -> angular_velocity, reaction -> reaction_moment), which must be present
whenever the vector is. Prints one line per problem and exits 1 if there is any, else prints
a summary and exits 0.
"""
import os
import sys
import xml.etree.ElementTree as ET

import h5py
import numpy as np

# XDMF Mixed cell codes -> node count (None: the count follows the code).
CELL_NODES = {1: None, 2: None, 3: None, 4: 3, 5: 4, 6: 4, 7: 5, 8: 6, 9: 8,
              34: 3, 35: 9, 36: 6, 37: 8, 38: 10, 39: 13, 40: 15, 48: 20}

# Nodal vector -> the nodal scalar holding its RZ component.
ROTATIONAL_PART = {"displacement": "rotation", "velocity": "angular_velocity",
                   "reaction": "reaction_moment", "support_reaction": "support_moment"}


def main(argv):
    args = argv[1:]
    want_grids = None
    if "--grids" in args:
        i = args.index("--grids")
        want_grids = int(args[i + 1])
        del args[i:i + 2]
    if len(args) != 1:
        print(__doc__)
        return 2
    xmf = args[0]
    errors = []
    err = errors.append
    try:
        root = ET.parse(xmf).getroot()
    except (ET.ParseError, OSError) as e:
        print(f"check_xdmf: error: cannot parse {xmf}: {e}")
        return 1
    base = os.path.dirname(os.path.abspath(xmf))
    files = {}

    def dataset(item):
        """The h5py dataset behind an HDF DataItem (None on error), after checking it."""
        if item.get("Format") != "HDF":
            err(f"DataItem not in HDF format: {item.attrib}")
            return None
        ref = (item.text or "").strip()
        if ":" not in ref:
            err(f"bad HDF reference {ref!r}")
            return None
        fname, path = ref.split(":", 1)
        fpath = os.path.join(base, fname)
        if fpath not in files:
            try:
                files[fpath] = h5py.File(fpath, "r")
            except OSError as e:
                err(f"cannot open {fpath}: {e}")
                files[fpath] = None
        f = files[fpath]
        if f is None:
            return None
        if path not in f or not isinstance(f[path], h5py.Dataset):
            err(f"{ref}: no such dataset")
            return None
        d = f[path]
        dims = tuple(int(x) for x in item.get("Dimensions", "").split())
        if d.shape != dims:
            err(f"{ref}: shape {d.shape} but Dimensions {dims}")
        ntype = item.get("NumberType", item.get("DataType", "Float"))
        kind = {"Float": "f", "Int": "i", "UInt": "u"}.get(ntype)
        if d.dtype.kind != kind:
            err(f"{ref}: dtype {d.dtype} but NumberType {ntype}")
        prec = int(item.get("Precision", "4"))
        if d.dtype.itemsize != prec:
            err(f"{ref}: item size {d.dtype.itemsize} but Precision {prec}")
        return d

    if root.tag != "Xdmf" or root.get("Version") != "3.0":
        err(f"root is <{root.tag} Version={root.get('Version')}>, expected <Xdmf Version=\"3.0\">")
    coll = root.find("Domain/Grid")
    if coll is None or coll.get("GridType") != "Collection" or coll.get("CollectionType") != "Temporal":
        err("Domain/Grid is not a temporal collection")
        coll = ET.Element("Grid")
    grids = coll.findall("Grid")
    times = []
    names = set()
    for g in grids:
        name = g.get("Name")
        if not name or name in names:
            err(f"grid name {name!r} missing or repeated")
        names.add(name)
        if g.get("GridType", "Uniform") != "Uniform":
            err(f"{name}: not a uniform grid")
        t = g.find("Time")
        try:
            times.append(float(t.get("Value")))
        except (AttributeError, TypeError, ValueError):
            err(f"{name}: missing or bad <Time Value=...>")
        topo, geom = g.find("Topology"), g.find("Geometry")
        if topo is None or geom is None:
            err(f"{name}: Topology or Geometry missing")
            continue
        if geom.get("GeometryType") != "XYZ":
            err(f"{name}: GeometryType is not XYZ")
        gd = dataset(geom.find("DataItem"))
        nnode = gd.shape[0] if gd is not None and len(gd.shape) == 2 and gd.shape[1] == 3 else None
        if nnode is None:
            err(f"{name}: geometry is not an (nnode, 3) array")
        # A DIMENSION 3 mesh (z not all zero): vectors are (x, y, z), no rotation scalars.
        solid = nnode is not None and bool(np.any(np.asarray(gd[:, 2]) != 0.0))
        if topo.get("TopologyType") != "Mixed":
            err(f"{name}: TopologyType is not Mixed")
        nelem = int(topo.get("NumberOfElements", "-1"))
        td = dataset(topo.find("DataItem"))
        if td is not None:
            a = np.asarray(td[()]).ravel()
            k, count = 0, 0
            while k < a.size:
                code = int(a[k]); k += 1
                if code not in CELL_NODES:
                    err(f"{name}: unknown cell code {code} at {k - 1}")
                    break
                n = CELL_NODES[code]
                if n is None:
                    n = int(a[k]); k += 1
                ids = a[k:k + n]; k += n
                if ids.size != n or (nnode is not None and (ids.min() < 0 or ids.max() >= nnode)):
                    err(f"{name}: cell {count} has bad node ids {ids.tolist()}")
                count += 1
            if count != nelem:
                err(f"{name}: topology holds {count} cells, NumberOfElements={nelem}")
        kinds = {}
        for att in g.findall("Attribute"):
            aname = att.get("Name")
            center, atype = att.get("Center"), att.get("AttributeType", "Scalar")
            kinds[aname] = (center, atype)
            item = att.find("DataItem")
            shape = None
            if item is not None and item.get("ItemType") == "HyperSlab":
                # a selection (start, stride, count rows of a 3 x rank XML array) of an HDF item
                parts = item.findall("DataItem")
                if len(parts) != 2 or parts[0].get("Format") != "XML":
                    err(f"{name}/{aname}: a HyperSlab needs an XML selection and a source DataItem")
                    continue
                d = dataset(parts[1])
                if d is None:
                    continue
                sel = np.array(parts[0].text.split(), dtype=int).reshape(3, -1)
                start, stride, count = sel
                if sel.shape[1] != len(d.shape) or np.any(start < 0) or np.any(
                        start + stride * (count - 1) >= np.array(d.shape)):
                    err(f"{name}/{aname}: hyperslab {sel.tolist()} outside {d.shape}")
                shape = tuple(int(c) for c in count)
                dims = tuple(int(x) for x in item.get("Dimensions", "").split())
                if dims != shape:
                    err(f"{name}/{aname}: hyperslab Dimensions {dims} but count {shape}")
            else:
                d = dataset(item)
                if d is None:
                    continue
                shape = d.shape
            rows = {"Node": nnode, "Cell": nelem}.get(center)
            if rows is None or shape[0] != rows:
                err(f"{name}/{aname}: {shape[0]} rows for Center={center}")
            ncomp = 1 if len(shape) == 1 else int(np.prod(shape[1:]))
            need = {"Scalar": 1, "Vector": 3, "Tensor": 9, "Tensor6": 6}.get(atype)
            if need is not None and ncomp != need:
                err(f"{name}/{aname}: {ncomp} components for AttributeType={atype}")
            if center == "Node" and atype == "Vector" and ncomp == 3 and len(d.shape) == 2 and not solid:
                z = np.asarray(d[:, 2])
                if np.any(z != 0.0):
                    err(f"{name}/{aname}: nodal Vector has a non-zero z component "
                        f"(max |z| = {np.max(np.abs(z))}); a 2-D field must be (x, y, 0)")
        for vec, rot in ROTATIONAL_PART.items():
            if vec in kinds and kinds.get(rot) != ("Node", "Scalar") and not solid:
                err(f"{name}: {vec} present but {rot} is not a nodal Scalar attribute")
    if want_grids is not None and len(grids) != want_grids:
        err(f"{len(grids)} grids, expected {want_grids}")
    if any(b < a for a, b in zip(times, times[1:])):
        err(f"times not increasing: {times}")
    for f in files.values():
        if f is not None:
            f.close()
    for e in errors:
        print("check_xdmf: error: " + e)
    if errors:
        return 1
    print(f"OK {xmf}: {len(grids)} grids, times {times}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
