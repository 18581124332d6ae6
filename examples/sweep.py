#!/usr/bin/env python3
"""A parameter sweep of drape runs on a Dask cluster: any scene keys x any values.

    python3 examples/sweep.py scenes/hang.json --seconds 2 \\
        --vary cloth.springs.structural.stiffness 500 2000 8000 \\
        --vary solver.method symplectic xpbd --csv sweep.csv --plot sweep.png --y max_strain

Every combination of the --vary values is one task: the scene with those keys overridden (as
`drape run --set KEY=VALUE` does; a value is JSON, a bare word a string), run headless by the
Python module on a worker, returning its stats (the keys of `drape run --stats`). A task whose
scene is bad reports its error in the table; the others go on. The results are written as a CSV
table (one row per task, in the order of the combinations) and, with --plot, a plot of one stat
against one varied key, a line for each combination of the other keys.

By default the tasks run on a LocalCluster on this machine (one single-threaded worker per
core); --scheduler tcp://HOST:8786 (or --scheduler-file) sends them to a running cluster, whose
workers need drape's Python module on their PYTHONPATH. The scene file is read here and sent as
a dict, so the workers need not see it. See the README, "Sweeps".
"""
import argparse
import csv
import itertools
import json
import os
import sys


def parse_value(text):
    """A --vary value as --set reads one: JSON, else a bare word as a string."""
    try:
        return json.loads(text)
    except json.JSONDecodeError:
        return text


def run_task(scene, overrides, seconds):
    """One task, on a worker: the stats of one run, or the reason the scene was refused."""
    import drape  # on the worker

    try:
        return {"stats": drape.run(scene, seconds=seconds, overrides=overrides), "error": None}
    except drape.InputError as error:
        return {"stats": None, "error": str(error)}


def cell(value):
    """A table cell: lists and dicts as JSON, None as empty."""
    if value is None:
        return ""
    if isinstance(value, (list, dict)):
        return json.dumps(value)
    return value


# The stats' columns in the README's order; keys it does not know follow.
STATS_ORDER = [
    "status", "diverged_frame", "message", "scene", "method", "particles", "springs", "frames",
    "dt", "sim_seconds", "substeps_per_frame", "wall_seconds", "setup_ms", "ms_per_frame",
    "state_bytes", "model_bytes", "workspace_bytes", "bytes_per_particle", "kinetic_energy",
    "max_strain", "mean_strain", "max_penetration", "pinned_drift", "finite",
]


def write_table(path, keys, rows):
    stats_keys = list(STATS_ORDER)
    for row in rows:
        for key in row["stats"] or {}:
            if key not in stats_keys:
                stats_keys.append(key)
    with open(path, "w", newline="") as f:
        out = csv.writer(f)
        out.writerow(keys + ["error"] + stats_keys)
        for row in rows:
            stats = row["stats"] or {}
            out.writerow([cell(row["overrides"][k]) for k in keys] + [cell(row["error"])] +
                         [cell(stats.get(k)) for k in stats_keys])


def plot(path, rows, keys, x_key, y_key, title):
    import matplotlib

    matplotlib.use("Agg")  # no display needed
    import matplotlib.pyplot as plt

    others = [k for k in keys if k != x_key]
    xs = [row["overrides"][x_key] for row in rows]
    numeric = all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in xs)
    categories = []
    for x in xs:
        if json.dumps(x) not in categories:
            categories.append(json.dumps(x))

    fig, ax = plt.subplots(figsize=(7, 4.5))
    groups = {}
    for row in rows:
        if row["stats"] is None or row["stats"].get(y_key) is None:
            continue
        label = ", ".join(f"{k}={json.dumps(row['overrides'][k])}" for k in others)
        x = row["overrides"][x_key]
        groups.setdefault(label, []).append(
            (x if numeric else categories.index(json.dumps(x)), row["stats"][y_key]))
    for label, points in groups.items():
        points.sort()
        ax.plot([p[0] for p in points], [p[1] for p in points], marker="o",
                label=label or None)
    if not numeric:
        ax.set_xticks(range(len(categories)), categories)
    elif min(xs) > 0 and max(xs) >= 10 * min(xs):  # values spread over decades
        ax.set_xscale("log")
    ax.set_xlabel(x_key)
    ax.set_ylabel(y_key)
    ax.set_title(title)
    ax.grid(True, alpha=0.3)
    if any(groups) and others:
        ax.legend(fontsize="small")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv=None):
    parser = argparse.ArgumentParser(
        description="A parameter sweep of drape runs on a Dask cluster.",
        formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__.split("\n\n")[1])
    parser.add_argument("scene", help="scene file (JSON)")
    parser.add_argument("--vary", nargs="+", action="append", metavar=("KEY", "VALUE"),
                        required=True, help="a scene key and the values it takes (JSON or a "
                        "bare word), e.g. --vary cloth.resolution [16,16] [32,32]; repeat for "
                        "more keys: every combination runs")
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                        help="a scene key set the same in every task")
    parser.add_argument("--seconds", type=float, help="simulated time of each run (default: the "
                        "scene's duration)")
    parser.add_argument("--scheduler", metavar="tcp://HOST:8786",
                        help="a running Dask scheduler (default: a LocalCluster here)")
    parser.add_argument("--scheduler-file", help="a running Dask scheduler's file "
                        "(dask scheduler --scheduler-file FILE)")
    parser.add_argument("--workers", type=int, default=os.cpu_count(),
                        help="LocalCluster workers, one task at a time each (default: cores)")
    parser.add_argument("--csv", default="sweep.csv", help="the table (default: sweep.csv)")
    parser.add_argument("--plot", help="a PNG of --y against --x")
    parser.add_argument("--x", help="the varied key on the plot's x axis (default: the first)")
    parser.add_argument("--y", default="max_strain", help="the stat plotted (default: max_strain)")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
    args = parser.parse_args(argv)

    keys = [v[0] for v in args.vary]
    if any(len(v) < 2 for v in args.vary):
        parser.error("--vary needs a key and at least one value")
    if len(set(keys)) != len(keys):
        parser.error("each key may be varied once")
    x_key = args.x or keys[0]
    if x_key not in keys:
        parser.error(f"--x {x_key}: not one of the varied keys ({', '.join(keys)})")
    try:
        with open(args.scene) as f:
            scene = json.load(f)
    except (OSError, json.JSONDecodeError) as error:
        print(f"sweep: {args.scene}: {error}", file=sys.stderr)
        return 2
    fixed = {}
    for assignment in args.set:
        key, _, value = assignment.partition("=")
        fixed[key] = parse_value(value)

    combinations = list(itertools.product(*[[parse_value(t) for t in v[1:]] for v in args.vary]))
    rows = [{"overrides": dict(zip(keys, values)), "stats": None, "error": None}
            for values in combinations]

    from dask.distributed import Client, LocalCluster, as_completed

    cluster = None
    if args.scheduler or args.scheduler_file:
        client = Client(args.scheduler, scheduler_file=args.scheduler_file)
    else:
        # One task per worker process: each run is single-threaded (the nanny sets
        # OMP_NUM_THREADS=1), so runs do not compete for cores.
        cluster = LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True,
                               host="127.0.0.1", dashboard_address=None)
        client = Client(cluster)
    try:
        futures = {}
        for index, row in enumerate(rows):
            overrides = {**fixed, **row["overrides"]}
            future = client.submit(run_task, scene, overrides, args.seconds, pure=False)
            futures[future] = index
        bar = None
        if not args.quiet:
            from tqdm import tqdm

            bar = tqdm(total=len(futures), unit="run", desc="sweep", file=sys.stderr)
        for future in as_completed(futures):
            row = rows[futures[future]]
            if future.status == "error":  # the task itself failed (a worker lost, ...)
                row["error"] = f"{type(future.exception()).__name__}: {future.exception()}"
            else:
                row.update(future.result())
            if bar:
                bar.update()
        if bar:
            bar.close()
    finally:
        client.close()
        if cluster:
            cluster.close()

    write_table(args.csv, keys, rows)
    failed = [row for row in rows if row["error"]]
    print(f"sweep: {len(rows) - len(failed)} of {len(rows)} runs done, table in {args.csv}")
    for row in failed:
        print(f"sweep: {json.dumps(row['overrides'])}: {row['error']}", file=sys.stderr)
    if args.plot:
        plot(args.plot, rows, keys, x_key, args.y, scene.get("name", args.scene))
        print(f"sweep: {args.y} against {x_key} in {args.plot}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
