"""Field snapshots as VTK files for ParaView: one ``.vtu`` per snapshot and a ``.pvd`` index.

XML UnstructuredGrid files (VTK file format version 1.0) with base64 binary
data arrays and a UInt64 header. Points are the reference node coordinates
(z = 0 in 2D); the point array ``displacement`` (L0) gives the deformed shape
(ParaView: Warp By Vector) and the cell array ``I1_sigma`` (/ E) the first
stress invariant. Q1 cells are VTK_QUAD (9); Q2 cells VTK_BIQUADRATIC_QUAD
(28), whose node order (corners, mid-edges bottom/right/top/left, centre) is
capslide's; H1 cells VTK_HEXAHEDRON (12) and H2 cells VTK_TRIQUADRATIC_HEXAHEDRON (29), in VTK's orders as
capslide's. The ``.pvd`` index carries ubar as its time value, so ParaView's time slider steps through the slide.
A 3D case's surface fields at the snapshots (gap, normal traction, the traction vector, slip state and slip at the
surface Gauss points) go to a second series of points (VTK_VERTEX, 1) placed at their current x, y on the
substrate's plane z = 0: a map of the contact plane. Files are
written atomically.
"""

from __future__ import annotations

import base64
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

from .atomic import replacing

__all__ = ["VTK_CELL_TYPES", "write_vtu", "write_pvd", "write_snapshot_series", "write_surface_series", "snapshot_steps"]

VTK_CELL_TYPES = {4: 9, 9: 28, 8: 12, 27: 29, 1: 1}  # nodes per cell -> VTK_QUAD, VTK_BIQUADRATIC_QUAD, VTK_HEXAHEDRON,
# VTK_TRIQUADRATIC_HEXAHEDRON, VTK_VERTEX
_VTK_TYPE_NAMES = {("f", 8): "Float64", ("f", 4): "Float32", ("i", 8): "Int64", ("u", 1): "UInt8"}


def _data_array(name: str, values: np.ndarray, components: int = 1) -> str:
    values = np.ascontiguousarray(values, dtype=values.dtype.newbyteorder("<"))  # the header says little endian
    raw = values.tobytes()
    payload = base64.b64encode(np.array(len(raw), dtype="<u8").tobytes() + raw).decode("ascii")
    kind = _VTK_TYPE_NAMES[(values.dtype.kind, values.dtype.itemsize)]
    return (f'<DataArray type="{kind}" Name={quoteattr(name)} '
            f'NumberOfComponents="{components}" format="binary">{payload}</DataArray>')


def _write_atomic(path: Path, text: str) -> None:
    with replacing(path) as tmp:
        tmp.write_text(text, encoding="utf-8")


def write_vtu(path: str | Path, nodes: np.ndarray, cells: np.ndarray, point_vectors: dict[str, np.ndarray],
              cell_scalars: dict[str, np.ndarray], point_scalars: dict[str, np.ndarray] | None = None) -> Path:
    """One unstructured grid: ``nodes`` (n, d), ``cells`` (m, 4, 9, 8, 27 or 1) node ids, point vectors (n, d), cell
    and point scalars (d = 2: padded with z = 0)."""
    path = Path(path)
    n, m = len(nodes), len(cells)
    if cells.shape[1] not in VTK_CELL_TYPES:
        raise ValueError(f"cells with {cells.shape[1]} nodes have no VTK type here (allowed: 4, 9, 8, 27, 1)")

    def three(a: np.ndarray) -> np.ndarray:
        return (a if a.shape[1] == 3 else np.column_stack([a, np.zeros(n)])).astype(np.float64)

    points = three(nodes)
    connectivity = cells.astype(np.int64).ravel()
    offsets = np.arange(1, m + 1, dtype=np.int64) * cells.shape[1]
    types = np.full(m, VTK_CELL_TYPES[cells.shape[1]], dtype=np.uint8)
    pdata = "".join(_data_array(k, three(v), 3) for k, v in point_vectors.items())
    pdata += "".join(_data_array(k, np.asarray(v, dtype=np.float64)) for k, v in (point_scalars or {}).items())
    cdata = "".join(_data_array(k, np.asarray(v, dtype=np.float64)) for k, v in cell_scalars.items())
    text = (
        '<?xml version="1.0"?>\n'
        '<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" header_type="UInt64">\n'
        f'<UnstructuredGrid><Piece NumberOfPoints="{n}" NumberOfCells="{m}">\n'
        f"<PointData>{pdata}</PointData>\n<CellData>{cdata}</CellData>\n"
        f"<Points>{_data_array('Points', points, 3)}</Points>\n"
        f"<Cells>{_data_array('connectivity', connectivity)}{_data_array('offsets', offsets)}"
        f"{_data_array('types', types)}</Cells>\n"
        "</Piece></UnstructuredGrid>\n</VTKFile>\n"
    )
    _write_atomic(path, text)
    return path


def write_pvd(path: str | Path, entries: list[tuple[float, str]]) -> Path:
    """A ParaView collection: (time value, file name relative to the .pvd) per dataset."""
    path = Path(path)
    rows = "".join(f'<DataSet timestep="{t:.12g}" part="0" file={quoteattr(f)}/>\n' for t, f in entries)
    _write_atomic(path, f'<?xml version="1.0"?>\n<VTKFile type="Collection" version="1.0">\n<Collection>\n{rows}'
                        "</Collection>\n</VTKFile>\n")
    return path


def write_snapshot_series(directory: str | Path, stem: str, nodes: np.ndarray, cells: np.ndarray, ubar: np.ndarray,
                          u: np.ndarray, v: np.ndarray, I1_sigma: np.ndarray, w: np.ndarray | None = None) -> Path:
    """Every snapshot k as ``{stem}_{k:03d}.vtu`` plus ``{stem}.pvd`` (time = ubar) in ``directory``; the .pvd path.
    ``u``, ``v`` (and in 3D ``w``): the displacement components, (snapshots, nodes)."""
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    entries = []
    for k in range(len(ubar)):
        name = f"{stem}_{k:03d}.vtu"
        parts = [u[k], v[k]] if w is None else [u[k], v[k], w[k]]
        write_vtu(directory / name, nodes, cells, {"displacement": np.column_stack(parts)},
                  {"I1_sigma": I1_sigma[k]})
        entries.append((float(ubar[k]), name))
    return write_pvd(directory / f"{stem}.pvd", entries)


def snapshot_steps(phase: np.ndarray, ubar: np.ndarray, snapshot_ubar: np.ndarray, slide: int) -> np.ndarray:
    """The step of each snapshot: the slide step at its ubar (``slide``: the slide's phase code), or for ubar = 0
    the last step before the slide (the preloaded state); -1 where no step matches."""
    out = np.full(len(snapshot_ubar), -1, dtype=np.int64)
    before = np.flatnonzero(phase != slide)
    for k, s in enumerate(snapshot_ubar):
        on = np.flatnonzero((phase == slide) & np.isclose(ubar, s, rtol=0.0, atol=1e-9 * max(1.0, abs(s))))
        out[k] = on[0] if len(on) else (before[-1] if s == 0.0 and len(before) else -1)
    return out


def write_surface_series(directory: str | Path, stem: str, ubar: np.ndarray, x: np.ndarray, y: np.ndarray,
                         scalars: dict[str, np.ndarray], traction: np.ndarray) -> Path:
    """The surface points at each snapshot k as ``{stem}_surface_{k:03d}.vtu`` plus ``{stem}_surface.pvd``:
    points at (x, y, 0) (snapshots, points), point ``scalars`` (name -> (snapshots, points)) and the traction
    vector (snapshots, points, 3); the .pvd path."""
    directory = Path(directory)
    entries = []
    for k in range(len(ubar)):
        name = f"{stem}_surface_{k:03d}.vtu"
        nodes = np.column_stack([x[k], y[k], np.zeros(len(x[k]))])
        cells = np.arange(len(nodes), dtype=np.int64)[:, None]
        write_vtu(directory / name, nodes, cells, {"traction": traction[k]}, {},
                  {key: v[k] for key, v in scalars.items()})
        entries.append((float(ubar[k]), name))
    return write_pvd(directory / f"{stem}_surface.pvd", entries)
