"""parallax.write: the format table's writers from Python, with the command line's fidelity (a
cloud read and written back gives the bytes `parallax convert` gives), and dicts of arrays."""

import warnings

import numpy as np
import pytest

import parallax


@pytest.mark.parametrize(
    "source,suffix",
    [
        ("laz/point-color-time.las", ".las"),
        ("laz/point10.las", ".las"),
        ("laz/extrabytes.las", ".las"),
        ("laz/point-color-time.las", ".laz"),
        ("laz/point-color-time.las", ".ply"),
        ("formats/pcd/autzen-utm.pcd", ".pcd"),
    ],
)
def test_written_bytes_equal_the_cli(source, suffix, data_dir, cli, tmp_path):
    path = data_dir / source
    by_cli = tmp_path / ("cli" + suffix)
    cli("convert", path, "-o", by_cli, "-q")
    by_module = tmp_path / ("module" + suffix)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # what the format has no place for: the CLI drops it too
        parallax.write(str(by_module), parallax.read(str(path)))
    assert by_module.read_bytes() == by_cli.read_bytes()


def test_las_read_and_written_is_the_same_file(data_dir, tmp_path):
    # As `parallax convert` gives it back (tests/io: the LAS round trip), so does write().
    source = data_dir / "laz/point-color-time.las"
    out = tmp_path / "same.las"
    parallax.write(out, parallax.read(str(source)))
    back = parallax.read(str(out))
    original = parallax.read(str(source))
    assert back.columns == original.columns
    for name in original.columns:
        np.testing.assert_array_equal(back[name], original[name], err_msg=name)
    assert [(v.user_id, v.record_id, v.data) for v in back.vlrs if v.user_id == "LASF_Projection"] == [
        (v.user_id, v.record_id, v.data) for v in original.vlrs if v.user_id == "LASF_Projection"
    ]


def test_a_write_through_a_view_reaches_the_file(generated, tmp_path):
    pc = parallax.read(str(generated["ply-binary"]))
    pc["red"][:] = 17
    pc["nz"][0] = 0.5
    out = tmp_path / "edited.ply"
    parallax.write(out, pc)
    back = parallax.read(str(out))
    assert (back["red"] == 17).all()
    assert back["nz"][0] == np.float32(0.5)
    np.testing.assert_array_equal(back["green"], pc["green"])


def test_colours_written_through_a_view_reach_a_las_file(data_dir, tmp_path):
    # A LAS source keeps its 16-bit colours beside the 8-bit display ones; a colour written
    # through pc["red"] must reach the file, by the reader's 8-bit rule, and the others stay.
    pc = parallax.read(str(data_dir / "laz/point-color-time.las"))  # 8-bit values in 16 bits
    before = np.array(pc.raw("green"))
    pc["red"][:] = 7
    pc["green"][0] = 200
    parallax.write(tmp_path / "eight.las", pc)
    back = parallax.read(str(tmp_path / "eight.las"))
    assert (back.raw("red") == 7).all()
    assert back.raw("green")[0] == 200
    np.testing.assert_array_equal(back.raw("green")[1:], before[1:])
    # 16-bit values: a changed point gets value * 257, the others keep every bit.
    n = 4
    parallax.write(tmp_path / "sixteen.las", {
        "x": np.arange(n, dtype=np.float64), "y": np.zeros(n), "z": np.zeros(n),
        "red": np.array([1000, 40000, 65535, 300], dtype=np.uint16),
        "green": np.array([5, 6, 7, 8], dtype=np.uint16),
        "blue": np.array([9, 10, 11, 12], dtype=np.uint16)})
    pc = parallax.read(str(tmp_path / "sixteen.las"))
    assert pc.raw("red").tolist() == [1000, 40000, 65535, 300]
    pc["red"][1] = 10
    parallax.write(tmp_path / "sixteen-edited.las", pc)
    back = parallax.read(str(tmp_path / "sixteen-edited.las"))
    assert back.raw("red").tolist() == [1000, 2570, 65535, 300]
    assert back.raw("green").tolist() == [5, 6, 7, 8]


def test_dict_of_arrays_round_trips(tmp_path):
    rng = np.random.default_rng(3)
    n = 1000
    arrays = {
        "x": 500000.0 + rng.uniform(0, 100, n),
        "y": 4000000.0 + rng.uniform(0, 100, n),
        "z": rng.uniform(0, 30, n),
        "red": rng.integers(0, 256, n, dtype=np.uint8),
        "green": rng.integers(0, 256, n, dtype=np.uint8),
        "blue": rng.integers(0, 256, n, dtype=np.uint8),
        "intensity": rng.integers(0, 65536, n).astype(np.uint16),
        "classification": rng.integers(0, 20, n, dtype=np.uint8),
        "quality": rng.standard_normal(n).astype(np.float32),
    }
    out = tmp_path / "arrays.ply"
    parallax.write(out, arrays)
    back = parallax.read(str(out))
    assert back.columns == list(arrays)
    # Positions sit on the finest power-of-two grid holding the bounds: exact to 2^-20 m here.
    for axis in "xyz":
        np.testing.assert_allclose(back[axis], arrays[axis], rtol=0, atol=2.0**-16)
    for name in ("red", "green", "blue", "classification", "quality"):
        np.testing.assert_array_equal(back[name], arrays[name], err_msg=name)
    np.testing.assert_array_equal(back["intensity"], arrays["intensity"].astype(np.float32))

    las = tmp_path / "arrays.las"
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        parallax.write(las, arrays, scale=(0.001, 0.001, 0.001), offset=(500000.0, 4000000.0, 0.0))
    back = parallax.read(str(las))
    assert back.scale == (0.001, 0.001, 0.001)
    assert back.offset == (500000.0, 4000000.0, 0.0)
    expected = np.round((arrays["x"] - 500000.0) / 0.001).astype(np.int32)
    np.testing.assert_array_equal(back.raw("x"), expected)
    np.testing.assert_array_equal(back["classification"], arrays["classification"])
    np.testing.assert_array_equal(back["intensity"], arrays["intensity"].astype(np.float32))
    # LAS has no 'quality' field: written as extra bytes, or reported as not kept.
    assert "quality" in back.columns or any("quality" in str(w.message) for w in caught)


def test_write_errors(tmp_path):
    with pytest.raises(ValueError, match="no 'z' column"):
        parallax.write(tmp_path / "a.ply", {"x": np.zeros(3), "y": np.zeros(3)})
    with pytest.raises(ValueError, match="column 'y': expected a 1-D array of 3"):
        parallax.write(tmp_path / "a.ply", {"x": np.zeros(3), "y": np.zeros(2), "z": np.zeros(3)})
    with pytest.raises(ValueError, match="column 'x', point 1: expected a finite"):
        parallax.write(tmp_path / "a.ply", {"x": np.array([0.0, np.nan]), "y": np.zeros(2), "z": np.zeros(2)})
    with pytest.raises(TypeError, match="PointCloud or a dict"):
        parallax.write(tmp_path / "a.ply", [1, 2, 3])
    with pytest.raises(parallax.InputError, match="a.unknown"):
        parallax.write(tmp_path / "a.unknown", {"x": np.zeros(3), "y": np.zeros(3), "z": np.zeros(3)})
    assert not (tmp_path / "a.ply").exists(), "nothing is left behind by a failed write"


def test_dict_types_reach_the_file(tmp_path):
    n = 50
    rng = np.random.default_rng(5)
    red = rng.integers(0, 65536, n).astype(np.uint16)
    arrays = {
        "x": rng.uniform(0, 10, n).astype(np.float32),
        "y": rng.uniform(0, 10, n).astype(np.float32),
        "z": rng.uniform(0, 10, n).astype(np.float32),
        "red": red,
        "green": red[::-1].copy(),
        "blue": np.full(n, 65535, np.uint16),
    }
    ply = tmp_path / "float.ply"
    parallax.write(ply, arrays)
    header = ply.read_bytes().split(b"end_header")[0].decode()
    assert "property float x" in header, header
    assert "property ushort red" in header, header
    # The file holds the float32 values given (x y z float, then ushort colours): within the
    # 2^-28 grid everywhere (core/quantization.h: positions are int32 on the finest power-of-two
    # grid that holds the bounds), bit for bit where a float32's ulp is far coarser (above 1).
    body = ply.read_bytes().split(b"end_header\n", 1)[1]
    records = np.frombuffer(body, dtype=[("xyz", "<f4", 3), ("rgb", "<u2", 3)])
    for axis, name in enumerate("xyz"):
        written, given = records["xyz"][:, axis], arrays[name]
        big = np.abs(given) >= 1.0
        np.testing.assert_array_equal(written[big], given[big])
        np.testing.assert_allclose(written, given, rtol=0, atol=2.0**-28)
    # PLY writes the display colour (8 bits) in the source's 16-bit type; LAS keeps the values.
    np.testing.assert_array_equal(records["rgb"][:, 0], np.round(red / 257.0).astype(np.uint16) * 257)
    # 16-bit colours kept as given in LAS (raw), shown as their nearest 8-bit value.
    las = tmp_path / "colour.las"
    parallax.write(las, arrays)
    back = parallax.read(str(las))
    np.testing.assert_array_equal(back.raw("red"), red)
    np.testing.assert_array_equal(back.raw("blue"), arrays["blue"])
    np.testing.assert_array_equal(back["red"], np.round(red / 257.0).astype(np.uint8))
