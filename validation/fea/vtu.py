"""ParaView output: one VTU per position of a sweep and a PVD that plays them as a time series.

Quadratic triangles (VTK_QUADRATIC_TRIANGLE: three vertices, then the mid-edge nodes of edges
0-1, 1-2, 2-0, which is scikit-fem's P2 dof order) at the P2 nodes, or linear triangles on a P1
mesh, member frame, metres. Point
data: displacement [m] (z = 0), sigma_xx, sigma_yy, tau_xy and von_mises [Pa]. Each file is
written to a temporary name in the same folder and then moved into place, so that a failure never
leaves a half-written file.
"""

from __future__ import annotations

import os
import tempfile
import xml.etree.ElementTree as ElementTree
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from linkstress.stress_state import von_mises
from linkstress.validation.fea.plane_stress import PlaneStressModel


def write_sweep(
    folder: Path,
    name: str,
    model: PlaneStressModel,
    displacement: NDArray[np.float64],
    nodal_stress: NDArray[np.float64],
) -> list[Path]:
    """Write ``name``_NNNN.vtu for each position and ``name``.pvd into ``folder``; return their paths."""
    import meshio  # a tenth of a second to import: only where fields are written, not for every FEA

    folder.mkdir(parents=True, exist_ok=True)
    scalar = model.scalar
    points = np.column_stack([scalar.doflocs.T, np.zeros(scalar.N)])
    cells = [("triangle6" if model.order == 2 else "triangle", scalar.element_dofs.T.copy())]
    stem = _safe(name)
    paths = []
    for p in range(displacement.shape[1]):
        u = np.column_stack(
            [displacement[model.components[0], p], displacement[model.components[1], p], np.zeros(scalar.N)]
        )
        s = nodal_stress[p]
        data = {
            "displacement": u,
            "sigma_xx": s[:, 0],
            "sigma_yy": s[:, 1],
            "tau_xy": s[:, 2],
            "von_mises": von_mises(s),
        }
        path = folder / f"{stem}_{p:04d}.vtu"
        mesh = meshio.Mesh(points, cells, point_data=data)
        _atomic(path, lambda tmp, mesh=mesh: meshio.write(tmp, mesh, file_format="vtu"))
        paths.append(path)
    pvd = folder / f"{stem}.pvd"
    _atomic(pvd, lambda tmp: _collection(paths).write(tmp, xml_declaration=True, encoding="utf-8"))
    return [*paths, pvd]


def _collection(paths: list[Path]) -> ElementTree.ElementTree:
    """A ParaView collection (PVD) listing ``paths`` as time steps 0, 1, ..."""
    root = ElementTree.Element("VTKFile", type="Collection", version="0.1")
    collection = ElementTree.SubElement(root, "Collection")
    for step, path in enumerate(paths):
        ElementTree.SubElement(collection, "DataSet", timestep=str(step), part="0", file=path.name)
    ElementTree.indent(root)
    return ElementTree.ElementTree(root)


def _safe(name: str) -> str:
    """A file stem from a link name: letters, digits, '-', '_' kept, anything else '_'."""
    return "".join(c if c.isalnum() or c in "-_" else "_" for c in name) or "link"


def _atomic(path: Path, write) -> None:
    handle, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    os.close(handle)
    try:
        write(tmp)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
