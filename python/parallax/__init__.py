"""Parallax: massive point clouds as numpy arrays.

    import parallax
    pc = parallax.read("scan.las", classes=[2])     # every format the command line reads
    x, y, z = pc["x"], pc["y"], pc["z"]            # float64 world coordinates
    pc["intensity"]                                  # a view of Parallax's own column, no copy
    parallax.write("ground.ply", pc)                 # every format it writes
    for chunk in parallax.read_chunks("huge.ply", points=5_000_000): ...
    octree = parallax.open_octree("https://host/city.copc.laz")  # Potree or COPC, local or http(s)
    part = octree.query(box=(x0, y0, z0, x1, y1, z1), level=5, classes=[6])
    image = parallax.render(part, width=800, height=600, edl=True)  # (600, 800, 3) uint8
    parallax.pick("scan.las", (400, 300), width=800, height=600)     # the point at that pixel

Bad input raises parallax.InputError (a ValueError) with the file, the byte offset or line and
what was expected. The compiled half is parallax._parallax (C++, pybind11); see docs/python.md.
"""

from ._parallax import (
    ChunkReader,
    InputError,
    Octree,
    OctreeNode,
    PointCloud,
    Vlr,
    convert,
    network_stats,
    open_octree,
    pick,
    process,
    read,
    read_chunks,
    read_header,
    render,
    write,
)

__all__ = [
    "ChunkReader",
    "InputError",
    "Octree",
    "OctreeNode",
    "PointCloud",
    "Vlr",
    "convert",
    "network_stats",
    "open_octree",
    "pick",
    "process",
    "read",
    "read_chunks",
    "read_header",
    "render",
    "write",
]
