"""parallax.read and read_chunks: every format's columns equal what `parallax convert` to text
writes, the arrays are views of the C++ columns, and bad input is a parallax.InputError."""

import numpy as np
import pytest

import parallax
from conftest import cli_text

SHARED_FILES = [
    "laz/point-color-time.las",
    "laz/point-color-time.las.laz",
    "laz/point10.las",
    "laz/extrabytes.las",
    "laz/extrabytes.laz",
    "laz/point-time-1.4.las.laz",
    "laz/simple.copc.laz",
    "formats/e57/A4.e57",
    "formats/pcd/autzen-utm.pcd",
    "formats/pts/autzen.pts",
    "formats/ptx/1.2-with-color.ptx",
]
GENERATED = ["ply-binary", "ply-ascii", "ply-binary-be", "las", "pcd"]


def assert_equals_cli_text(pc, text):
    assert pc.columns == list(text), "the same columns, in the same order"
    for name, expected in text.items():
        values = np.asarray(pc[name], dtype=np.float64)
        assert values.shape == expected.shape, name
        if name in ("x", "y", "z"):
            # The text holds the decimal the scale allows; read back it is the double nearest
            # it, which raw * scale + offset may miss by an ulp.
            np.testing.assert_allclose(values, expected, rtol=1e-12, atol=0, err_msg=name)
        else:
            np.testing.assert_array_equal(values.astype(np.float32), expected.astype(np.float32), err_msg=name)


@pytest.mark.parametrize("name", SHARED_FILES)
def test_shared_file_equals_cli_text(name, data_dir, cli, tmp_path):
    path = data_dir / name
    pc = parallax.read(str(path))
    assert len(pc) > 0
    assert_equals_cli_text(pc, cli_text(cli, path, tmp_path))


@pytest.mark.parametrize("kind", GENERATED)
def test_generated_file_equals_cli_text(kind, generated, cli, tmp_path):
    pc = parallax.read(str(generated[kind]))
    assert len(pc) == 3000
    assert_equals_cli_text(pc, cli_text(cli, generated[kind], tmp_path))


def test_ply_columns_types_and_metadata(generated):
    pc = parallax.read(str(generated["ply-binary"]))
    assert pc.format == "ply"
    assert pc.columns == ["x", "y", "z", "nx", "ny", "nz", "red", "green", "blue"]
    assert pc["x"].dtype == np.float64
    assert pc["red"].dtype == np.uint8
    assert pc["nx"].dtype == np.float32
    assert pc.point_format is None and pc.vlrs == [] and pc.crs_wkt is None
    lo, hi = pc.bounds
    assert lo == (pc["x"].min(), pc["y"].min(), pc["z"].min())
    assert hi == (pc["x"].max(), pc["y"].max(), pc["z"].max())


def test_las_metadata(data_dir):
    pc = parallax.read(str(data_dir / "laz/point-color-time.las"))
    assert pc.format == "las"
    assert pc.point_format == 3
    assert pc.las_version == "1.2"
    assert pc.scale == (0.01, 0.01, 0.01)
    assert "EPSG:26910" in pc.crs
    projection = [(v.user_id, v.record_id) for v in pc.vlrs if v.user_id == "LASF_Projection"]
    assert ("LASF_Projection", 34735) in projection
    geokeys = next(v for v in pc.vlrs if v.record_id == 34735)
    assert len(geokeys.data) == geokeys.data_size > 0
    # GeoKeyDirectoryTag header: KeyDirectoryVersion 1 (LAS 1.4 R15 2.5.1), little endian.
    assert int.from_bytes(geokeys.data[0:2], "little") == 1
    assert pc["gps_time"].dtype == np.float64
    assert pc["scan_angle_rank"].dtype == np.int8
    assert pc["point_source_id"].dtype == np.uint16
    assert pc.raw("red").dtype == np.uint16


def test_wkt_crs_of_a_las_1_4_file(data_dir):
    pc = parallax.read(str(data_dir / "laz/simple.copc.laz"))
    assert pc.las_version == "1.4"
    assert pc.crs_wkt is not None and pc.crs_wkt.startswith(("PROJCS", "COMPD_CS", "GEOGCS", "PROJCRS", "COMPOUNDCRS"))


def test_columns_are_views_of_the_cloud(data_dir):
    pc = parallax.read(str(data_dir / "laz/point-color-time.las"))
    intensity = pc["intensity"]
    assert intensity.base is pc, "the array's base is the cloud that owns the column"
    again = pc["intensity"]
    assert np.shares_memory(intensity, again)
    before = float(again[5])
    intensity[5] = before + 1000
    assert again[5] == before + 1000, "a write through one view is seen by another"
    assert pc.to_dict()["intensity"][5] == before + 1000
    red = pc["red"]
    assert red.strides == (4,), "a channel of the RGBA column, not a copy"
    assert np.shares_memory(red, pc["green"]) is False
    # The cloud outlives every reference but the array's.
    gps = pc["gps_time"]
    first = float(gps[0])
    del pc
    assert float(gps[0]) == first


def test_item_assignment_writes_the_column(data_dir):
    # docs/python.md's `ground["intensity"] *= 0.5`: in place, then handed back to __setitem__.
    pc = parallax.read(str(data_dir / "laz/point-color-time.las"))
    before = np.array(pc["intensity"])
    view = pc["intensity"]
    pc["intensity"] *= 0.5
    np.testing.assert_array_equal(pc["intensity"], before * np.float32(0.5))
    assert np.shares_memory(view, pc["intensity"]) and view[3] == before[3] * np.float32(0.5)
    pc["classification"] = 9
    assert set(pc["classification"].tolist()) == {9}
    pc["user_data"] = np.arange(len(pc)) % 7
    assert pc["user_data"].tolist() == [i % 7 for i in range(len(pc))]
    with pytest.raises(ValueError, match=r'read only.*raw\("x"\)'):
        pc["x"] = np.zeros(len(pc))
    with pytest.raises(KeyError, match="no_such"):
        pc["no_such"] = 1
    with pytest.raises(ValueError):
        pc["intensity"] = np.zeros(3)  # numpy: 3 values cannot broadcast to 1065
    raw_x = np.array(pc.raw("x"))
    assert pc.raw("x").tolist() == raw_x.tolist(), "the failed writes changed nothing"


def test_raw_positions_scale_and_offset(data_dir):
    pc = parallax.read(str(data_dir / "laz/point-color-time.las"))
    raw = pc.raw("x")
    assert raw.dtype == np.int32 and raw.strides == (12,)
    assert raw.base is pc
    assert np.shares_memory(raw, pc.raw("y")) is False
    for axis, name in enumerate("xyz"):
        world = pc.raw(name).astype(np.float64) * pc.scale[axis] + pc.offset[axis]
        np.testing.assert_array_equal(world, pc[name])
    x = pc["x"]
    assert x.flags.writeable is False, "world x is derived from the int32 positions"
    assert np.shares_memory(x, pc["x"]), "computed once and kept"
    with pytest.raises(ValueError):
        x[0] = 1.0


def test_columns_argument_keeps_only_those(data_dir):
    pc = parallax.read(str(data_dir / "laz/point-color-time.las"), ["gps_time", "intensity"])
    assert pc.columns == ["x", "y", "z", "intensity", "gps_time"]
    with pytest.raises(KeyError, match="no column 'nope'.*gps_time"):
        parallax.read(str(data_dir / "laz/point-color-time.las"), ["nope"])


@pytest.mark.parametrize("name", ["laz/point-time-1.4.las.laz", "laz/simple.copc.laz", "laz/extrabytes.laz"])
def test_columns_argument_of_laz_equals_the_whole_read(name, data_dir):
    """LAZ readers skip the layers not asked for (formats 6-10); the columns read are the same."""
    path = str(data_dir / name)
    whole = parallax.read(path)
    wanted = [c for c in whole.columns if c not in ("x", "y", "z")][-1:]
    some = parallax.read(path, wanted)
    assert some.columns == ["x", "y", "z"] + wanted
    for column in ["x", "y", "z"] + wanted:
        np.testing.assert_array_equal(some[column], whole[column], err_msg=column)
    positions = parallax.read(path, [])
    assert positions.columns == ["x", "y", "z"]
    np.testing.assert_array_equal(positions.raw("z"), whole.raw("z"))


def test_filters_equal_a_numpy_filter_of_the_whole(data_dir):
    path = str(data_dir / "laz/point-color-time.las")
    whole = parallax.read(path)
    x, y, z = whole["x"], whole["y"], whole["z"]
    cls = whole["classification"]

    kept = parallax.read(path, classes=[2])
    np.testing.assert_array_equal(kept["gps_time"], whole["gps_time"][cls == 2])
    assert 0 < len(kept) < len(whole)

    box = (494200.0, 4877800.0, 0.0, 494600.0, 4878400.0, 1000.0)
    inside = (x >= box[0]) & (x <= box[3]) & (y >= box[1]) & (y <= box[4]) & (z >= box[2]) & (z <= box[5])
    kept = parallax.read(path, clip_box=box)
    np.testing.assert_array_equal(kept["gps_time"], whole["gps_time"][inside])
    kept = parallax.read(path, clip_box=box, clip_mode="outside")
    np.testing.assert_array_equal(kept["gps_time"], whole["gps_time"][~inside])

    first = whole["return_number"] == 1
    kept = parallax.read(path, returns=["first"])
    np.testing.assert_array_equal(kept["gps_time"], whole["gps_time"][first])

    band = (whole["intensity"] >= 50) & (whole["intensity"] <= 150)
    kept = parallax.read(path, intensity=(50, 150))
    np.testing.assert_array_equal(kept["gps_time"], whole["gps_time"][band])

    # A triangle: the even-odd test by hand.
    triangle = [(494000.0, 4877400.0), (495000.0, 4877400.0), (494000.0, 4878900.0)]
    below = (x > 494000.0) & (y > 4877400.0) & ((x - 494000.0) / 1000.0 + (y - 4877400.0) / 1500.0 < 1.0)
    kept = parallax.read(path, clip_polygon=triangle)
    assert len(kept) == int(below.sum())
    np.testing.assert_array_equal(kept["gps_time"], whole["gps_time"][below])


def test_filter_arguments_errors(data_dir):
    path = str(data_dir / "laz/point-color-time.las")
    with pytest.raises(ValueError, match="classes: expected class numbers 0-255"):
        parallax.read(path, classes=[300])
    with pytest.raises(ValueError, match="returns: unknown kind 'firsts'"):
        parallax.read(path, returns=["firsts"])
    with pytest.raises(ValueError, match=r"clip_box: expected \(xmin"):
        parallax.read(path, clip_box=(1, 2, 3))
    with pytest.raises(ValueError, match="clip_mode"):
        parallax.read(path, clip_box=(0, 0, 0, 1, 1, 1), clip_mode="around")


@pytest.mark.parametrize("kind", ["ply-binary", "ply-ascii", "las"])
def test_read_chunks_equal_the_whole(kind, generated):
    path = str(generated[kind])
    whole = parallax.read(path)
    chunks = parallax.read_chunks(path, points=700)
    assert chunks.point_count == 3000
    sizes, xs, reds = [], [], []
    for chunk in chunks:
        sizes.append(len(chunk))
        xs.append(np.array(chunk["x"]))
        reds.append(np.array(chunk["red"]))
    assert sizes == [700, 700, 700, 700, 200]
    np.testing.assert_allclose(np.concatenate(xs), whole["x"], rtol=1e-12, atol=0)
    np.testing.assert_array_equal(np.concatenate(reds), whole["red"])


def test_errors_are_input_errors_naming_the_file(tmp_path, generated):
    assert issubclass(parallax.InputError, ValueError)
    truncated = tmp_path / "truncated.ply"
    truncated.write_bytes(generated["ply-binary"].read_bytes()[:2000])
    with pytest.raises(parallax.InputError, match="truncated.ply") as error:
        parallax.read(str(truncated))
    assert "byte" in str(error.value) or "offset" in str(error.value)
    missing = tmp_path / "missing.las"
    with pytest.raises(parallax.InputError, match="missing.las"):
        parallax.read(str(missing))
    garbage = tmp_path / "garbage.bin"
    garbage.write_bytes(bytes(range(256)) * 4)
    with pytest.raises(parallax.InputError, match="garbage.bin"):
        parallax.read(str(garbage))
    with pytest.raises(parallax.InputError, match="truncated.ply"):
        list(parallax.read_chunks(str(truncated), points=100))
    with pytest.raises(ValueError, match="points: expected a positive"):
        parallax.read_chunks(str(generated["las"]), points=0)


def test_read_header_without_the_points(data_dir, generated):
    header = parallax.read_header(str(data_dir / "laz/point-color-time.las"))
    pc = parallax.read(str(data_dir / "laz/point-color-time.las"))
    assert header["format"] == "las"
    assert header["point_count"] == len(pc) == 1065
    # The header's declared bounds (doubles as LAS stores them) against the points' own.
    np.testing.assert_allclose(np.array(header["bounds"]), np.array(pc.bounds), rtol=1e-15, atol=0)
    assert header["point_format"] == 3 and header["las_version"] == "1.2"
    assert header["crs"] == pc.crs
    assert [v.record_id for v in header["vlrs"]] == [v.record_id for v in pc.vlrs]
    ply = parallax.read_header(str(generated["ply-binary"]))
    assert ply["format"] == "ply" and ply["point_count"] == 3000
    assert ply["bounds"] is None
    assert ply["point_format"] is None and ply["vlrs"] == []
    with pytest.raises(parallax.InputError, match="nothing.las"):
        parallax.read_header(str(data_dir / "nothing.las"))


def test_progress_callback(generated, data_dir):
    calls = []
    pc = parallax.read(str(generated["ply-binary"]), progress=lambda done, total: calls.append((done, total)))
    assert calls, "called at least once"
    assert calls[-1] == (3000, 3000)
    assert all(total == 3000 for _, total in calls)
    assert [done for done, _ in calls] == sorted(done for done, _ in calls)
    assert len(pc) == 3000

    def stop(done, total):
        raise RuntimeError("stopped by the callback")

    with pytest.raises(RuntimeError, match="stopped by the callback"):
        parallax.read(str(data_dir / "laz/point-color-time.las"), progress=stop)
