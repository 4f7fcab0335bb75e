"""python3 -m parallax_dask IN... -o OUT --scheduler tcp://HOST:PORT | --local-workers N"""

import argparse
import json
import os
import shutil
import sys

from .driver import ConversionError, convert


def parse_arguments(argv):
    parser = argparse.ArgumentParser(
        prog="python3 -m parallax_dask",
        description="Build the Potree 2.0 octree of point files on a Dask cluster: the same "
                    "bytes as `parallax convert IN... -o OUT` on one machine.")
    parser.add_argument("inputs", nargs="+", metavar="IN", help="point files (PLY, LAS, LAZ, text)")
    parser.add_argument("-o", "--output", required=True,
                        help="the Potree directory to write (on storage the workers share)")
    where = parser.add_mutually_exclusive_group(required=True)
    where.add_argument("--scheduler", help="a running Dask scheduler, tcp://HOST:PORT")
    where.add_argument("--local-workers", type=int,
                       help="start a local cluster of this many single-threaded workers")
    parser.add_argument("--parallax", default=shutil.which("parallax"),
                        help="the parallax executable, at the same path on every worker "
                             "(default: the one on PATH)")
    parser.add_argument("--work-dir", help="the shared work directory (default: .OUT.work "
                                           "beside the output); removed at the end")
    parser.add_argument("--tasks", type=int, default=16,
                        help="ranges of the inputs, and groups of chunks to build (default 16)")
    parser.add_argument("--build-tasks", type=int,
                        help="groups of chunks to build (default: --tasks); more groups balance "
                             "the builds better, each costs a task")
    parser.add_argument("--task-threads", type=int, default=1,
                        help="threads of each task (default 1: one task per worker thread)")
    parser.add_argument("--retries", type=int, default=2,
                        help="runs of a failed task after the first (default 2); bad input "
                             "is never retried")
    parser.add_argument("--memory", type=int, help="memory budget of each task in MB "
                                                   "(parallax convert --memory; default 2048)")
    parser.add_argument("--sampling", choices=("poisson", "random"))
    parser.add_argument("--spacing", type=float)
    parser.add_argument("--columns", help="text inputs: the columns, e.g. x,y,z,r,g,b")
    parser.add_argument("--classes", help="keep only these ASPRS classes, e.g. 2,6,9-12")
    parser.add_argument("--clip-box",
                        help="keep the points in XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX[,YAW] (YAW: "
                        "degrees the box turns about its vertical axis, counter-clockwise)")
    parser.add_argument("--clip-mode", choices=("inside", "outside"))
    parser.add_argument("--keep-work", action="store_true",
                        help="keep the work directory (task files) at the end")
    parser.add_argument("--report", help="write the stage and task times (JSON) to this file")
    parser.add_argument("-q", "--quiet", action="store_true", help="no progress, no report")
    options = parser.parse_args(argv)
    if not options.parallax:
        parser.error("no parallax executable on PATH: give --parallax PATH")
    options.parallax = os.path.abspath(options.parallax)
    if options.local_workers is not None and options.local_workers < 1:
        parser.error("--local-workers: at least 1")
    if options.tasks < 1:
        parser.error("--tasks: at least 1")
    return options


def main(argv=None):
    options = parse_arguments(sys.argv[1:] if argv is None else argv)
    try:
        report = convert(options)
    except ConversionError as error:
        sys.stderr.write(f"parallax_dask: error: {error}\n")
        return error.status
    except KeyboardInterrupt:
        sys.stderr.write("parallax_dask: interrupted; nothing written\n")
        return 130
    if options.report:
        with open(options.report, "w", encoding="utf-8") as out:
            json.dump(report, out, indent=2)
    if not options.quiet:
        points = max((t.get("points", 0) for t in report["tasks"] if t["stage"] == "finish"),
                     default=0)
        sys.stderr.write(f"wrote {report['output']}: {points} points, {len(report['tasks'])} "
                         f"tasks on {report['workers']} workers, {report['seconds']:.2f} s\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
