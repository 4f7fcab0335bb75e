"""Parallax's distributed octree build on Dask: `python3 -m parallax_dask IN... -o OUT`.

The driver (driver.py) writes the plan with `parallax convert --plan` and runs its tasks,
`parallax convert-task STAGE PLAN --part I`, on the workers of a Dask cluster (tasks.py).
"""
