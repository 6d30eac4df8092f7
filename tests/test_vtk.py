"""The VTK export of a 3D case's surface fields (issue 39, item 7): the snapshot's step, and the point series that
ParaView reads, decoded back from its base64 arrays."""

import base64
import xml.etree.ElementTree as ET

import numpy as np

from capslide.io.vtk import snapshot_steps, write_surface_series
from capslide.states import Phase

_TYPES = {"Float64": "<f8", "Int64": "<i8", "UInt8": "u1"}


def _arrays(path) -> dict[str, np.ndarray]:
    """Every DataArray of a .vtu written with a UInt64 header, by name, shaped (n, components)."""
    out = {}
    for a in ET.parse(path).getroot().iter("DataArray"):
        raw = base64.b64decode(a.text)
        values = np.frombuffer(raw[8:8 + int(np.frombuffer(raw[:8], "<u8")[0])], _TYPES[a.get("type")])
        out[a.get("Name")] = values.reshape(-1, int(a.get("NumberOfComponents")))
    return out


def test_a_snapshot_is_the_slide_step_at_its_ubar_and_zero_the_preloaded_state():
    P, S = int(Phase.PRELOAD), int(Phase.SLIDE)
    phase = np.array([int(Phase.APPROACH), P, P, S, S, S])
    ubar = np.array([0.0, 0.0, 0.0, 0.4, 1.0, 1.5])
    np.testing.assert_array_equal(snapshot_steps(phase, ubar, np.array([0.0, 1.0, 1.5, 2.0]), S), [2, 4, 5, -1])


def test_the_surface_series_holds_the_fields_at_the_current_points(tmp_path):
    rng = np.random.default_rng(3)
    x, y = rng.normal(size=(2, 5)), rng.normal(size=(2, 5))
    gap, traction = rng.normal(size=(2, 5)), rng.normal(size=(2, 5, 3))
    pvd = write_surface_series(tmp_path, "case", np.array([0.0, 1.5]), x, y, {"gap": gap}, traction)
    assert pvd.name == "case_surface.pvd" and 'timestep="1.5"' in pvd.read_text()
    a = _arrays(tmp_path / "case_surface_001.vtu")
    np.testing.assert_array_equal(a["Points"], np.column_stack([x[1], y[1], np.zeros(5)]))
    np.testing.assert_array_equal(a["gap"].ravel(), gap[1])
    np.testing.assert_array_equal(a["traction"], traction[1])
    np.testing.assert_array_equal(a["connectivity"].ravel(), np.arange(5))
    np.testing.assert_array_equal(a["types"].ravel(), np.ones(5))  # VTK_VERTEX


def test_a_triquadratic_cell_is_vtks_triquadratic_hexahedron(tmp_path):
    """H2 cells go out as VTK_TRIQUADRATIC_HEXAHEDRON (29) with capslide's node order, which is VTK's: the corners
    and the mid-edge, mid-face and centre nodes at the reference points VTK lists."""
    from capslide.fem.element import HEXES
    from capslide.io.vtk import write_vtu

    nodes = HEXES["H2"].nodes  # one cell: the reference cube
    write_vtu(tmp_path / "h2.vtu", nodes, np.arange(27)[None], {"displacement": nodes}, {"I1_sigma": np.ones(1)})
    a = _arrays(tmp_path / "h2.vtu")
    np.testing.assert_array_equal(a["types"].ravel(), [29])
    # VTK's triquadratic hexahedron: mid-edge nodes on (0,1) (1,2) (2,3) (3,0) (4,5) (5,6) (6,7) (7,4) (0,4) (1,5) (2,6)
    # (3,7); mid-face nodes on the faces x = -1, x = 1, y = -1, y = 1, z = -1, z = 1; then the centre
    pairs = [(0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7), (7, 4), (0, 4), (1, 5), (2, 6), (3, 7)]
    P = a["Points"]
    np.testing.assert_array_equal(P[8:20], [(P[i] + P[j]) / 2 for i, j in pairs])
    np.testing.assert_array_equal(P[20:26], [[-1, 0, 0], [1, 0, 0], [0, -1, 0], [0, 1, 0], [0, 0, -1], [0, 0, 1]])
    np.testing.assert_array_equal(P[26], [0, 0, 0])
