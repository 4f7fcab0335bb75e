"""parallax.render and parallax.pick: the picture equals the PNG `parallax render` writes with the
same options, byte for byte (decoded here with zlib by hand, not by the product's PNG code), and
the picked point equals `parallax pick --json`."""

import json
import struct
import zlib

import numpy as np
import pytest

import parallax


def decode_png(path):
    """An 8-bit RGB or RGBA PNG as an (H, W, channels) array: chunks, zlib, and the five row
    filters of the PNG specification (section 9), written out here."""
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", path
    at, idat, header = 8, b"", None
    while at < len(data):
        (length,) = struct.unpack(">I", data[at : at + 4])
        kind, body = data[at + 4 : at + 8], data[at + 8 : at + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        at += 12 + length
    width, height, depth, color_type, _, _, interlace = header
    assert depth == 8 and interlace == 0 and color_type in (2, 6), header
    channels = 3 if color_type == 2 else 4
    raw = zlib.decompress(idat)
    stride = width * channels
    rows = np.zeros((height, stride), dtype=np.uint8)
    previous = np.zeros(stride, dtype=np.int32)
    for y in range(height):
        start = y * (stride + 1)
        kind = raw[start]
        line = np.frombuffer(raw, dtype=np.uint8, count=stride, offset=start + 1).astype(np.int32)
        out = np.zeros(stride, dtype=np.int32)
        if kind == 0:
            out = line
        elif kind == 2:
            out = (line + previous) & 0xFF
        else:
            for i in range(stride):
                left = out[i - channels] if i >= channels else 0
                up = previous[i]
                corner = previous[i - channels] if i >= channels else 0
                if kind == 1:
                    predictor = left
                elif kind == 3:
                    predictor = (left + up) // 2
                elif kind == 4:
                    p = left + up - corner
                    pa, pb, pc = abs(p - left), abs(p - up), abs(p - corner)
                    predictor = left if pa <= pb and pa <= pc else (up if pb <= pc else corner)
                else:
                    raise AssertionError(f"filter type {kind} in row {y}")
                out[i] = (line[i] + predictor) & 0xFF
        rows[y] = out
        previous = out
    return rows.reshape(height, width, channels)


def cli_picture(cli, source, tmp_path, *options):
    png = tmp_path / "cli.png"
    cli("render", source, "-o", png, "-q", *options)
    image = decode_png(png)
    if image.shape[2] == 4:
        assert (image[:, :, 3] == 255).all(), "an opaque picture"
    return image[:, :, :3]


def test_png_decoder_reads_every_filter(tmp_path):
    """The decoder above against a PNG built here with each row filter, from known pixels."""
    pixels = np.random.default_rng(3).integers(0, 256, size=(5, 4, 3), dtype=np.uint8)
    stream = b""
    previous = np.zeros(12, dtype=np.int32)
    for y, kind in enumerate([0, 1, 2, 3, 4]):
        row = pixels[y].reshape(-1).astype(np.int32)
        filtered = np.zeros(12, dtype=np.int32)
        for i in range(12):
            left = row[i - 3] if i >= 3 else 0
            up, corner = previous[i], (previous[i - 3] if i >= 3 else 0)
            p = left + up - corner
            paeth = (
                left
                if abs(p - left) <= abs(p - up) and abs(p - left) <= abs(p - corner)
                else (up if abs(p - up) <= abs(p - corner) else corner)
            )
            predictor = [0, left, up, (left + up) // 2, paeth][kind]
            filtered[i] = (row[i] - predictor) & 0xFF
        stream += bytes([kind]) + filtered.astype(np.uint8).tobytes()
        previous = row

    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))

    png = tmp_path / "filters.png"
    png.write_bytes(
        b"\x89PNG\r\n\x1a\n"
        + chunk(b"IHDR", struct.pack(">IIBBBBB", 4, 5, 8, 2, 0, 0, 0))
        + chunk(b"IDAT", zlib.compress(stream))
        + chunk(b"IEND", b"")
    )
    np.testing.assert_array_equal(decode_png(png), pixels)


SCENES = [
    ({}, []),
    (
        {"eye": (30.0, -40.0, 25.0), "target": (0.0, 0.0, 0.0), "point_size": 3, "shape": "round"},
        ["--eye", "30,-40,25", "--target", "0,0,0", "--point-size", "3", "--shape", "round"],
    ),
    ({"size_mode": "adaptive", "edl": True, "color": "elevation"}, ["--size-mode", "adaptive", "--edl", "--color", "elevation"]),
    ({"stereo": "anaglyph", "background": (20, 30, 40)}, ["--stereo", "anaglyph", "--background", "20,30,40"]),
    ({"stereo": "sbs", "rasterizer": "points", "fov": 40}, ["--stereo", "sbs", "--rasterizer", "points", "--fov", "40"]),
]


@pytest.mark.parametrize("options, words", SCENES)
def test_render_equals_the_command_png(options, words, generated, cli, tmp_path):
    source = str(generated["ply-binary"])
    expected = cli_picture(cli, source, tmp_path, "--width", 160, "--height", 120, *words)
    image = parallax.render(source, width=160, height=120, **options)
    assert image.dtype == np.uint8 and image.shape == (120, 160, 3)
    assert (image != image[0, 0]).any(axis=2).sum() > 100, "points drawn"
    np.testing.assert_array_equal(image, expected)


def test_render_of_a_point_cloud_and_an_octree(generated, cli, tmp_path):
    las = str(generated["las"])
    expected = cli_picture(cli, las, tmp_path, "--width", 96, "--height", 64, "--color", "intensity")
    np.testing.assert_array_equal(parallax.render(parallax.read(las), width=96, height=64, color="intensity"), expected)
    copc = tmp_path / "scan.copc.laz"
    cli("convert", las, "-o", copc, "-q")
    expected = cli_picture(cli, copc, tmp_path, "--width", 96, "--height", 64, "--budget", 1000, "--classes", "0-1")
    np.testing.assert_array_equal(parallax.render(copc, width=96, height=64, budget=1000, classes=[0, 1]), expected)


def test_render_defaults_are_the_commands(generated, cli, tmp_path):
    source = str(generated["ply-binary"])
    image = parallax.render(source)
    assert image.shape == (720, 1280, 3)
    np.testing.assert_array_equal(image, cli_picture(cli, source, tmp_path))


@pytest.mark.parametrize("pixel", [(80, 60), (3, 3), (120, 40)])
def test_pick_equals_the_command_json(pixel, generated, cli):
    source = str(generated["las"])
    words = ["--width", 160, "--height", 120, "--point-size", 4]
    expected = json.loads(cli("pick", source, "--pixel", f"{pixel[0]},{pixel[1]}", "--json", *words))
    got = parallax.pick(source, pixel, width=160, height=120, point_size=4)
    if expected["found"]:
        expected["pixel"] = tuple(expected["pixel"])
        expected["point_pixel"] = tuple(expected["point_pixel"])
    assert got == expected
    if pixel == (80, 60):
        assert got["found"] and set(got["point"]) >= {"x", "y", "z", "intensity"}


def test_render_and_pick_errors(generated, tmp_path):
    source = str(generated["ply-binary"])
    with pytest.raises(TypeError, match="unexpected keyword argument 'colour'"):
        parallax.render(source, colour="rgb")
    with pytest.raises(ValueError, match="--point-size"):
        parallax.render(source, point_size=0)
    with pytest.raises(ValueError, match="stereo"):
        parallax.render(source, width=8, height=8, stereo="wobble")
    with pytest.raises(ValueError, match="--eye"):
        parallax.render(source, eye=(1, 2))
    with pytest.raises(ValueError, match="outside the 16x16 picture"):
        parallax.pick(source, (16, 0), width=16, height=16)
    truncated = tmp_path / "truncated.ply"
    truncated.write_bytes(open(source, "rb").read()[:2000])
    with pytest.raises(parallax.InputError, match="truncated.ply"):
        parallax.render(str(truncated), width=8, height=8)
