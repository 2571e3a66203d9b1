"""Converts every image of a folder on a Dask cluster, with one panoproj.Plan per worker.

    python dask_convert_folder.py IN_DIR OUT_DIR --to fisheye:fov=180 [--size 1024x1024]
        [--from equirect] [--workers 2] [--scheduler tcp://host:8786]

The plan is scattered once with broadcast=True: every worker unpickles it once (a Plan pickles
as its parameters), builds its map on its first image and reuses it for the rest. Each worker
runs its conversions with threads=1 and Dask runs one task per worker thread, so the cores are
shared by processes, not oversubscribed. All images of the folder must have the plan's source size.
Without --scheduler a LocalCluster of --workers processes is started on this machine.
"""
import argparse
import pathlib

import panoproj as pp

EXTENSIONS = {".jpg", ".jpeg", ".png", ".tif", ".tiff", ".exr", ".hdr"}


def convert_one(plan, src, out):
    """One image: read, convert with the worker's plan, write atomically."""
    from dask.distributed import get_worker

    worker = get_worker()
    if not hasattr(worker, "panoproj_plans"):
        worker.panoproj_plans = set()
    worker.panoproj_plans.add(id(plan))
    pp.write(out, plan(pp.read(src)), overwrite=True)
    return out


def plans_held(dask_worker):
    """How many distinct plan objects this worker has used (client.run(plans_held))."""
    return len(getattr(dask_worker, "panoproj_plans", ()))


def convert_folder(client, plan, in_dir, out_dir, ext=".png"):
    """Converts in_dir's images into out_dir (same stems, extension ext); returns the paths."""
    in_dir, out_dir = pathlib.Path(in_dir), pathlib.Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    sources = sorted(p for p in in_dir.iterdir() if p.suffix.lower() in EXTENSIONS)
    shared = client.scatter(plan, broadcast=True)
    futures = [client.submit(convert_one, shared, str(p), str(out_dir / (p.stem + ext)), pure=False)
               for p in sources]
    return client.gather(futures)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("in_dir")
    ap.add_argument("out_dir")
    ap.add_argument("--to", required=True, help="target projection spec")
    ap.add_argument("--from", dest="src", default="equirect", help="source projection spec")
    ap.add_argument("--size", help="output WxH")
    ap.add_argument("--interp", default="bicubic")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--scheduler", help="address of a running scheduler")
    ap.add_argument("--ext", default=".png")
    a = ap.parse_args()
    from dask.distributed import Client, LocalCluster

    first = next(p for p in sorted(pathlib.Path(a.in_dir).iterdir()) if p.suffix.lower() in EXTENSIONS)
    h, w = pp.read(str(first)).shape[:2]
    plan = pp.Plan(a.src, a.to, (w, h), size=a.size, interp=a.interp, threads=1)
    if a.scheduler:
        with Client(a.scheduler) as client:
            written = convert_folder(client, plan, a.in_dir, a.out_dir, a.ext)
    else:
        with LocalCluster(n_workers=a.workers, threads_per_worker=1) as cluster, Client(cluster) as client:
            written = convert_folder(client, plan, a.in_dir, a.out_dir, a.ext)
    print(f"{len(written)} images written to {a.out_dir}")


if __name__ == "__main__":
    main()
