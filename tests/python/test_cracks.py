"""A torn sheet from Python: damage views, the crack graph, the render mesh's pieces."""
import numpy as np
import pytest

import shellfrac


@pytest.fixture(scope="module")
def torn():
    from conftest import TINY_TEAR
    sim = shellfrac.Simulation(shellfrac.Scene.from_dict(TINY_TEAR), threads=2)
    sim.advance_to(TINY_TEAR["time"]["end"])
    return sim


def test_damage_views(torn):
    c, c_his = torn.damage("sheet"), torn.damage_history("sheet")
    assert c.shape == (144 * 16, 3) and c_his.shape == c.shape  # 12 x 12 cells, 4 x 4 points, 3 layers
    assert not c.flags.writeable
    assert ((c >= 0) & (c <= 1)).all()
    assert (c_his >= c).all()  # c_his is the largest c so far
    assert torn.metrics()["max_damage"] in (c.max(), c_his.max())


def test_crack_graph(torn):
    vertices, edges = torn.crack_graph("sheet")
    assert vertices.shape[1] == 2 and edges.shape[1] == 2
    assert len(edges) == torn.metrics()["cracks"]["crack_segments"]
    assert edges.min() >= 0 and edges.max() < len(vertices)
    # The crack runs from the notch (its tip at xi = (0.3, 0.5)) across the sheet.
    assert vertices[:, 0].max() > 0.6


def test_render_mesh_labels_are_the_pieces(torn):
    mesh = torn.render_mesh("sheet")
    m = torn.metrics(mesh=True)
    labels = mesh["labels"]
    assert len(labels) == len(mesh["faces"]) == len(mesh["face_offsets"]) - 1
    assert len(set(labels[labels >= 0])) == m["pieces"] + m["slivers"]["count"]
    # Area per label from the triangles, against the piece areas the metrics report.
    v, t = mesh["vertices"], mesh["triangles"]
    tri_area = 0.5 * np.linalg.norm(np.cross(v[t[:, 1]] - v[t[:, 0]], v[t[:, 2]] - v[t[:, 0]]), axis=1)
    per_label = np.bincount(labels[mesh["triangle_faces"]], weights=tri_area)
    big = np.sort(per_label[per_label >= torn.dx ** 2])
    np.testing.assert_allclose(big, np.sort(m["piece_areas"]), rtol=1e-9)
    # Torn in exactly two (measured: areas 0.907 and 0.093 m^2), with no slivers beside them.
    assert m["pieces"] == 2 and len(m["piece_areas"]) == 2
    assert m["slivers"]["count"] == 0
