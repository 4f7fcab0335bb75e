"""parallax.open_octree: a COPC file and a Potree 2.0 directory, their hierarchy, and queries that
equal a brute-force numpy filter of the whole cloud read with parallax.read (exact points)."""

import numpy as np
import pytest

import parallax


POINTS = 40000  # enough for several levels (the converter's nodes hold up to some thousands)


@pytest.fixture(scope="module")
def octrees(cli, tmp_path_factory):
    """A generated scan as LAS, and its COPC file and Potree directory."""
    folder = tmp_path_factory.mktemp("octrees")
    ply, las = folder / "scan.ply", folder / "scan.las"
    copc, potree = folder / "scan.copc.laz", folder / "scan_potree"
    cli("generate", "-o", ply, "--points", POINTS, "--seed", 7, "-q")
    cli("convert", ply, "-o", las, "-q")
    cli("convert", las, "-o", copc, "-q")
    cli("convert", las, "-o", potree, "--format", "potree", "-q")
    return {"las": las, "copc": copc, "potree": potree}


def raw_rows(pc):
    """The points as rows of int32 positions, sorted: a set that order does not change."""
    rows = np.stack([pc.raw("x"), pc.raw("y"), pc.raw("z")], axis=1)
    return rows[np.lexsort(rows.T[::-1])]


def grid_rows(pc, scale, offset, keep=None):
    """The points of `pc` (world coordinates) on the grid `scale`, `offset`, sorted."""
    columns = []
    for axis, name in enumerate("xyz"):
        values = np.asarray(pc[name]) if keep is None else np.asarray(pc[name])[keep]
        columns.append(np.round((values - offset[axis]) / scale[axis]).astype(np.int64))
    rows = np.stack(columns, axis=1)
    return rows[np.lexsort(rows.T[::-1])]


def in_box(pc, box):
    x, y, z = pc["x"], pc["y"], pc["z"]
    return (x >= box[0]) & (x <= box[3]) & (y >= box[1]) & (y <= box[4]) & (z >= box[2]) & (z <= box[5])


def sub_box(bounds, low, high):
    """The part of `bounds` from fraction `low` to `high` of each axis."""
    lo, hi = np.array(bounds[0]), np.array(bounds[1])
    return tuple(lo + (hi - lo) * low) + tuple(lo + (hi - lo) * high)


def test_copc_metadata_and_hierarchy(octrees):
    octree = parallax.open_octree(str(octrees["copc"]))
    whole = parallax.read(str(octrees["copc"]))
    assert octree.format == "copc"
    assert octree.point_count == len(whole) == POINTS
    np.testing.assert_allclose(octree.bounds, whole.bounds, rtol=0, atol=1e-9)
    nodes = octree.nodes()
    assert nodes[0].name == "r" and nodes[0].level == 0
    assert sum(node.point_count for node in nodes) == POINTS
    counts = octree.level_point_counts
    assert octree.levels == len(counts) >= 2
    assert sum(counts) == POINTS
    for node in nodes:
        assert node.spacing == pytest.approx(octree.spacing / 2**node.level)
        assert len(node.name) == node.level + 1


@pytest.mark.parametrize("kind", ["copc", "potree"])
def test_whole_query_equals_the_source(kind, octrees):
    octree = parallax.open_octree(str(octrees[kind]))
    everything = octree.query()
    assert len(everything) == POINTS
    source = parallax.read(str(octrees["las"]))
    np.testing.assert_array_equal(raw_rows(everything), grid_rows(source, everything.scale, everything.offset))


def test_copc_box_and_polygon_equal_a_numpy_filter(octrees):
    path = str(octrees["copc"])
    octree = parallax.open_octree(path)
    whole = parallax.read(path)
    box = sub_box(whole.bounds, 0.2, 0.65)
    expected = in_box(whole, box)
    assert 0 < expected.sum() < len(whole)
    report = {}
    got = octree.query(box=box, report=report)
    assert len(got) == int(expected.sum())
    np.testing.assert_array_equal(raw_rows(got), grid_rows(whole, got.scale, got.offset, expected))
    # Only the nodes the box meets are read.
    assert 0 < report["nodes_read"] <= report["nodes_total"]

    (x0, y0, _), (x1, y1, _) = whole.bounds
    triangle = [(x0 - 1.0, y0 - 1.0), (x1 + 1.0, y0 - 1.0), (x0 - 1.0, y1 + 1.0)]
    x, y = whole["x"], whole["y"]
    below = (x - (x0 - 1.0)) / (x1 - x0 + 2.0) + (y - (y0 - 1.0)) / (y1 - y0 + 2.0) < 1.0
    got = octree.query(polygon=triangle)
    assert 0 < len(got) == int(below.sum()) < len(whole)
    np.testing.assert_array_equal(raw_rows(got), grid_rows(whole, got.scale, got.offset, below))


@pytest.mark.parametrize("kind", ["copc", "potree"])
def test_levels_are_the_additive_subsets(kind, octrees):
    octree = parallax.open_octree(str(octrees[kind]))
    counts = octree.level_point_counts
    everything = octree.query()
    for level in range(len(counts)):
        report = {}
        got = octree.query(level=level, report=report)
        assert len(got) == sum(counts[: level + 1])
        assert report["level"] == level
    # A level and a box: the box's points of that level's cloud.
    coarse = octree.query(level=1)
    box = sub_box(everything.bounds, 0.1, 0.7)
    got = octree.query(level=1, box=box)
    np.testing.assert_array_equal(
        raw_rows(got), grid_rows(coarse, coarse.scale, coarse.offset, in_box(coarse, box))
    )
    # A spacing: the first level at least that fine.
    report = {}
    octree.query(spacing=octree.spacing / 2 * 1.01, report=report)
    assert report["level"] == 1
    octree.query(spacing=octree.spacing * 10, report=report)
    assert report["level"] == 0
    octree.query(spacing=octree.spacing / 2**40, report=report)
    assert report["level"] == len(counts) - 1


def test_classes_of_a_real_copc_file(data_dir):
    path = str(data_dir / "laz/simple.copc.laz")
    octree = parallax.open_octree(path)
    whole = parallax.read(path)
    ground = whole["classification"] == 2
    assert 0 < ground.sum() < len(whole)
    got = octree.query(classes=[2])
    np.testing.assert_array_equal(raw_rows(got), grid_rows(whole, got.scale, got.offset, ground))
    assert set(np.unique(got["classification"])) == {2}
    assert "gps_time" in got.columns


def test_query_progress_counts_to_the_nodes_points(octrees):
    octree = parallax.open_octree(str(octrees["potree"]))
    calls = []
    octree.query(progress=lambda done, total: calls.append((done, total)))
    assert calls and calls[-1] == (POINTS, POINTS)
    assert all(total == POINTS for _, total in calls)


def test_octree_errors(octrees, tmp_path):
    with pytest.raises(parallax.InputError, match="scan.las"):
        parallax.open_octree(str(octrees["las"]))
    with pytest.raises(parallax.InputError):
        parallax.open_octree(str(tmp_path / "missing"))
    octree = parallax.open_octree(str(octrees["copc"]))
    with pytest.raises(ValueError, match="level, spacing: give one of them"):
        octree.query(level=1, spacing=1.0)
    with pytest.raises(ValueError, match="level: expected 0"):
        octree.query(level=-1)
    with pytest.raises(ValueError, match="spacing: expected a positive distance"):
        octree.query(spacing=0)
    with pytest.raises(ValueError, match="clip_box"):
        octree.query(box=(1, 2, 3))
