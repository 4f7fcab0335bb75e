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


def _vlr_tuples(vlrs):
    return [(v.user_id, v.record_id, v.data) for v in vlrs]


def test_las_header_metadata_of_a_url_equals_the_local_one(served, data_dir):
    # A file with a CRS in GeoTIFF records: point format, version and every VLR (their bytes too),
    # from parallax.read and parallax.read_header, as the local file gives them.
    root, base, _ = served
    shutil.copy(data_dir / "laz/point-color-time.las", root / "crs.las")
    local = parallax.read(str(root / "crs.las"))
    remote = parallax.read(f"{base}/crs.las")
    assert (remote.point_format, remote.las_version) == (3, "1.2")
    assert (remote.point_format, remote.las_version) == (local.point_format, local.las_version)
    assert ("LASF_Projection", 34735) in [(v.user_id, v.record_id) for v in remote.vlrs]
    assert _vlr_tuples(remote.vlrs) == _vlr_tuples(local.vlrs)
    assert remote.crs == local.crs and "EPSG:26910" in remote.crs
    header = parallax.read_header(f"{base}/crs.las")
    assert (header["point_format"], header["las_version"]) == (3, "1.2")
    assert _vlr_tuples(header["vlrs"]) == _vlr_tuples(local.vlrs)


@pytest.mark.parametrize("name", ["scan.ply", "scan.las"])
def test_read_chunks_of_a_url_equal_the_local_chunks(name, served):
    root, base, _ = served
    local = list(parallax.read_chunks(str(root / name), points=700))
    chunks = parallax.read_chunks(f"{base}/{name}", points=700)
    assert chunks.point_count == 3000
    remote = list(chunks)
    assert [len(part) for part in remote] == [700, 700, 700, 700, 200]
    assert all(part.path == f"{base}/{name}" for part in remote)
    assert remote[0].columns == local[0].columns
    for ours, theirs in zip(remote, local):
        for column in theirs.columns:
            np.testing.assert_array_equal(ours[column], theirs[column], err_msg=column)
    whole = parallax.read(str(root / name))
    np.testing.assert_allclose(np.concatenate([part["x"] for part in remote]), whole["x"],
                               rtol=1e-12, atol=0)
    if name.endswith(".las"):
        assert remote[0].point_format == whole.point_format == 2
        assert remote[0].raw("x").tolist() == local[0].raw("x").tolist()


def test_render_and_pick_of_a_point_file_url_equal_the_local_file(served):
    # As `parallax render URL` and `pick URL` do: a point file within the budget is read from
    # its URL and drawn whole, the picture and the picked point those of the local file.
    root, base, _ = served
    options = dict(width=96, height=64)
    local = parallax.render(str(root / "scan.las"), **options)
    remote = parallax.render(f"{base}/scan.las", **options)
    assert remote.shape == (64, 96, 3)
    assert local.any()
    np.testing.assert_array_equal(remote, local)
    # A pixel a point was drawn on (not the background of the corner).
    rows, cols = np.nonzero((local != local[0, 0]).any(axis=2))
    pixel = (int(cols[len(cols) // 2]), int(rows[len(rows) // 2]))
    picked = parallax.pick(f"{base}/scan.las", pixel, **options)
    assert picked["found"]
    assert picked == parallax.pick(str(root / "scan.las"), pixel, **options)
