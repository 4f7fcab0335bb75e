"""http(s) URLs: parallax.read of a file a real nginx serves on loopback equals the local read,
and parallax.open_octree queries a COPC file and a Potree directory by range, fetching the
nodes the query reads rather than the file."""

import shutil

import numpy as np
import pytest

import parallax


@pytest.fixture(scope="module")
def served(nginx, generated, cli):
    root, base, log = nginx
    shutil.copy(generated["ply-binary"], root / "scan.ply")
    shutil.copy(generated["las"], root / "scan.las")
    # Octrees of several levels, so that a box meets some nodes and not others.
    cli("generate", "-o", root / "big.ply", "--points", 40000, "--seed", 7, "-q")
    cli("convert", root / "big.ply", "-o", root / "scan.copc.laz", "-q")
    cli("convert", root / "big.ply", "-o", root / "scan_potree", "--format", "potree", "-q")
    return root, base, log


@pytest.mark.parametrize("name", ["scan.ply", "scan.las"])
def test_read_of_a_url_equals_the_local_read(name, served):
    root, base, _ = served
    local = parallax.read(str(root / name))
    remote = parallax.read(f"{base}/{name}")
    assert remote.columns == local.columns
    for column in local.columns:
        np.testing.assert_array_equal(remote[column], local[column], err_msg=column)
    assert remote.path == f"{base}/{name}"


@pytest.mark.parametrize("name", ["scan.copc.laz", "scan_potree/"])
def test_octree_query_over_http_equals_the_local_one(name, served):
    root, base, _ = served
    local = parallax.open_octree(str(root / name))
    remote = parallax.open_octree(f"{base}/{name}")
    assert remote.point_count == local.point_count
    assert remote.level_point_counts == local.level_point_counts
    (x0, y0, z0), (x1, y1, z1) = local.bounds
    box = (x0, y0, z0, x0 + (x1 - x0) / 3, y0 + (y1 - y0) / 3, z1)
    expected, report = local.query(box=box), {}
    before = parallax.network_stats()["bytes_received"]
    got = remote.query(box=box, report=report)
    fetched = parallax.network_stats()["bytes_received"] - before
    assert len(got) == len(expected) > 0
    for column in expected.columns:
        np.testing.assert_array_equal(got[column], expected[column], err_msg=column)
    # The nodes the box meets, not the whole file.
    assert report["nodes_read"] < report["nodes_total"]
    assert 0 < fetched
    if name.endswith(".laz"):
        assert fetched < (root / name).stat().st_size


def test_a_missing_url_is_an_input_error(served):
    _, base, _ = served
    with pytest.raises(parallax.InputError, match="missing.ply"):
        parallax.read(f"{base}/missing.ply")
    with pytest.raises(parallax.InputError, match="missing.copc.laz"):
        parallax.open_octree(f"{base}/missing.copc.laz")
