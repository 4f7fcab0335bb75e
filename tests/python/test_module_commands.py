"""parallax.convert and parallax.process: the files equal the command line's byte for byte, the
progress callback counts each stage to its total, and errors are the command's."""

import filecmp
from pathlib import Path

import pytest

import parallax


def same_tree(a, b):
    """Two files, or two directories holding the same files with the same bytes."""
    a, b = Path(a), Path(b)
    if a.is_file():
        return filecmp.cmp(a, b, shallow=False)
    names = sorted(p.name for p in a.iterdir())
    assert names == sorted(p.name for p in b.iterdir())
    return all(filecmp.cmp(a / n, b / n, shallow=False) for n in names)


CONVERSIONS = [
    ("scan.las", {}, []),
    ("scan.laz", {"point_format": 7, "las_version": "1.4"}, ["--point-format", "7", "--las-version", "1.4"]),
    ("scan.copc.laz", {}, []),
    ("scan_potree", {"format": "potree", "sampling": "random"}, ["--format", "potree", "--sampling", "random"]),
    ("ground.ply", {"clip_box": (-20, -20, -100, 20, 20, 100), "ascii": True}, ["--clip-box", "-20,-20,-100,20,20,100", "--ascii"]),
]


@pytest.mark.parametrize("name, options, words", CONVERSIONS)
def test_convert_equals_the_command(name, options, words, generated, cli, tmp_path):
    source = generated["ply-binary"]
    ours, theirs = tmp_path / "py" / name, tmp_path / "cli" / name
    ours.parent.mkdir()
    theirs.parent.mkdir()
    parallax.convert(str(source), ours, **options)
    cli("convert", source, "-o", theirs, "-q", *words)
    assert same_tree(ours, theirs), name


def test_convert_progress_counts_each_stage(generated, tmp_path):
    calls = []
    parallax.convert(
        generated["las"], tmp_path / "octree", format="potree",
        progress=lambda done, total, stage: calls.append((stage, done, total)),
    )
    stages = {stage for stage, _, _ in calls}
    assert len(stages) >= 2, calls
    for stage in stages:
        last = [(done, total) for s, done, total in calls if s == stage][-1]
        assert last[1] is None or last[0] == last[1], (stage, last)


@pytest.mark.parametrize("source, target", [("ply-binary", "scan.las"), ("las", "scan.ply")])
def test_single_file_convert_reports_reading_and_writing(source, target, generated, tmp_path):
    # A file to a file: no octree stages, but the read and the write report to the callback
    # (they drew terminal bars only), each ending at its total, the cloud's 3000 points.
    calls = []
    parallax.convert(
        generated[source], tmp_path / target,
        progress=lambda done, total, stage: calls.append((stage, done, total)),
    )
    stages = [stage for stage, _, _ in calls]
    assert set(stages) == {"reading", "writing"}, calls
    assert stages.index("writing") > max(i for i, s in enumerate(stages) if s == "reading")
    for stage in ("reading", "writing"):
        done = [(d, t) for s, d, t in calls if s == stage]
        assert all(t == 3000 for _, t in done), (stage, done)
        assert [d for d, _ in done] == sorted(d for d, _ in done), (stage, done)
        assert done[-1] == (3000, 3000), (stage, done)
    assert len(parallax.read(str(tmp_path / target))) == 3000


PROCESSING = [
    ([("normals", 12)], {}, ["--normals", "12"]),
    ([("normals", 8), ("curvature", True), ("subsample", "voxel:0.5")], {}, ["--normals", "8", "--curvature", "--subsample", "voxel:0.5"]),
    ({"outliers": "statistical:8,2"}, {"ascii": True}, ["--outliers", "statistical:8,2", "--ascii"]),
]


@pytest.mark.parametrize("steps, options, words", PROCESSING)
def test_process_equals_the_command(steps, options, words, generated, cli, tmp_path):
    source = generated["las"]
    ours, theirs = tmp_path / "py.ply", tmp_path / "cli.ply"
    parallax.process(source, ours, steps=steps, **options)
    cli("process", source, "-o", theirs, "-q", *words)
    assert same_tree(ours, theirs)


def test_process_progress_and_step_order(generated, tmp_path):
    calls = []
    parallax.process(
        generated["las"], tmp_path / "out.las", steps=[("normals", 8)],
        progress=lambda done, total, stage: calls.append((stage, done, total)),
    )
    assert calls, "the steps report progress"


def test_command_errors(generated, tmp_path):
    truncated = tmp_path / "truncated.ply"
    truncated.write_bytes(open(generated["ply-binary"], "rb").read()[:2000])
    with pytest.raises(parallax.InputError, match="truncated.ply"):
        parallax.convert(truncated, tmp_path / "out.las")
    assert not (tmp_path / "out.las").exists()
    with pytest.raises(TypeError, match="unexpected keyword argument 'colour'"):
        parallax.convert(generated["las"], tmp_path / "x.las", colour=1)
    with pytest.raises(ValueError, match="--normals"):
        parallax.process(generated["las"], tmp_path / "x.ply", steps=[("normals", "many")])
    with pytest.raises(ValueError, match="steps: expected"):
        parallax.process(generated["las"], tmp_path / "x.ply", steps=[("normals",)])

    def fails(done, total, stage):
        raise KeyboardInterrupt("stop")

    with pytest.raises(KeyboardInterrupt):
        parallax.convert(generated["las"], tmp_path / "stopped", format="potree", progress=fails)
