"""Parallax: massive point clouds as numpy arrays.

    import parallax
    pc = parallax.read("scan.las", classes=[2])     # every format the command line reads
    x, y, z = pc["x"], pc["y"], pc["z"]            # float64 world coordinates
    pc["intensity"]                                  # a view of Parallax's own column, no copy
    parallax.write("ground.ply", pc)                 # every format it writes
    for chunk in parallax.read_chunks("huge.ply", points=5_000_000): ...

Bad input raises parallax.InputError (a ValueError) with the file, the byte offset or line and
what was expected. The compiled half is parallax._parallax (C++, pybind11); see docs/python.md.
"""

from ._parallax import (
    ChunkReader,
    InputError,
    PointCloud,
    Vlr,
    read,
    read_chunks,
    write,
)

__all__ = [
    "ChunkReader",
    "InputError",
    "PointCloud",
    "Vlr",
    "read",
    "read_chunks",
    "write",
]
