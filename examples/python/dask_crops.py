"""One frame rendered as N×M crops on a dask.distributed cluster, reassembled, and checked byte for
byte against the same frame rendered whole.

Every pixel pointshade renders is a pure function of the scene and the pixel's coordinates
(docs/sampling.md, "Splitting a frame over machines"), so crops rendered by any worker, in any
order, with any thread count, put together are the whole-frame render exactly. Each crop is one
task, `pointshade.render(scene, crop=(x0, y0, x1, y1), width=W, height=H, spp=S, threads=1)`, on a
local cluster of two single-threaded worker processes (or an existing cluster: --scheduler);
the driver gathers the (h, w, 3) float32 crops, places them in one (H, W, 3) array, renders the
frame itself, and compares: `np.array_equal` and `.tobytes()` equality. Exits 1 on a mismatch,
and 0 with a SKIPPED line when dask.distributed is not installed.

The scene path is made absolute from the repository (the folder above examples/), so workers find
it whatever their working directory; with --scheduler, the workers must see the same file system
and have pointshade installed.

    python examples/python/dask_crops.py [--scene scenes/cornell-box.toml] [--tiles 3x2] [--width 160 --height 120 --spp 4] [--scheduler tcp://HOST:8786]
"""

import argparse
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))


def render_crop(scene, crop, width, height, spp, threads):
    """One task: the crop's pixels, (y1 − y0, x1 − x0, 3) float32. Runs on a worker."""
    import pointshade

    return pointshade.render(scene, crop=crop, width=width, height=height, spp=spp, threads=threads)["color"]


def split(length, parts):
    """`parts` consecutive intervals covering [0, length), as equal as integers allow."""
    edges = [length * i // parts for i in range(parts + 1)]
    return list(zip(edges[:-1], edges[1:]))


def crops_of(width, height, columns, rows):
    return [(x0, y0, x1, y1) for (y0, y1) in split(height, rows) for (x0, x1) in split(width, columns)]


def parse_tiles(text):
    try:
        columns, rows = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected COLUMNSxROWS such as 3x2, got {text!r}")
    if columns < 1 or rows < 1:
        raise argparse.ArgumentTypeError(f"need at least one column and one row, got {text!r}")
    return columns, rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", default=os.path.join("scenes", "cornell-box.toml"), help="relative to the repository, or absolute")
    parser.add_argument("--tiles", type=parse_tiles, default=(3, 2), help="COLUMNSxROWS of crops (default 3x2)")
    parser.add_argument("--width", type=int, default=160)
    parser.add_argument("--height", type=int, default=120)
    parser.add_argument("--spp", type=int, default=4)
    parser.add_argument("--threads", type=int, default=1, help="threads per crop render (default 1: one core per single-threaded worker)")
    parser.add_argument("--scheduler", help="address of an existing dask scheduler (default: a local cluster of 2 worker processes)")
    args = parser.parse_args()

    import pointshade

    try:
        from dask.distributed import Client, LocalCluster
    except ImportError:
        print("\n*** SKIPPED: dask.distributed is not installed (pip install 'dask[distributed]')\n", file=sys.stderr)
        return 0

    scene = os.path.normpath(os.path.join(REPO, args.scene))
    if not os.path.isfile(scene):
        sys.exit(f"error: {scene}: no such scene file")
    columns, rows = args.tiles
    if columns > args.width or rows > args.height:
        sys.exit(f"error: {columns}x{rows} crops do not fit in {args.width}x{args.height} pixels")
    crops = crops_of(args.width, args.height, columns, rows)

    t0 = time.perf_counter()
    if args.scheduler:
        cluster = None
        client = Client(args.scheduler)
    else:
        cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
        client = Client(cluster)
    started_s = time.perf_counter() - t0
    try:
        workers = len(client.scheduler_info()["workers"])
        t0 = time.perf_counter()
        futures = [
            client.submit(render_crop, scene, crop, args.width, args.height, args.spp, args.threads, pure=False)
            for crop in crops
        ]
        parts = client.gather(futures)
        crops_s = time.perf_counter() - t0
    finally:
        client.close()
        if cluster is not None:
            cluster.close()

    frame = np.zeros((args.height, args.width, 3), dtype=np.float32)
    for (x0, y0, x1, y1), part in zip(crops, parts):
        if part.shape != (y1 - y0, x1 - x0, 3) or part.dtype != np.float32:
            sys.exit(f"error: crop {(x0, y0, x1, y1)} came back as {part.dtype} {part.shape}")
        frame[y0:y1, x0:x1] = part

    t0 = time.perf_counter()
    whole = pointshade.render(scene, width=args.width, height=args.height, spp=args.spp)["color"]
    whole_s = time.perf_counter() - t0

    print(f"{os.path.relpath(scene, REPO)}: {args.width}x{args.height}, {args.spp} spp, {columns}x{rows} = {len(crops)} crops")
    print(f"  cluster: {'scheduler ' + args.scheduler if args.scheduler else 'local'}, {workers} workers (ready in {started_s:.2f} s)")
    print(f"  crops on the cluster: {crops_s:.2f} s; whole frame in this process: {whole_s:.2f} s")
    equal = np.array_equal(frame, whole)
    same_bytes = frame.tobytes() == whole.tobytes()
    if equal and same_bytes:
        print(f"  identical: np.array_equal and .tobytes() ({frame.nbytes} bytes, peak {frame.max():.4g})")
        return 0
    differ = np.any(frame != whole, axis=-1)
    print(
        f"FAILED: the assembled crops differ from the whole frame (array_equal {equal}, bytes equal {same_bytes}): "
        f"{int(differ.sum())} pixels, largest difference {float(np.abs(frame - whole).max()):.3e}",
        file=sys.stderr,
    )
    return 1


if __name__ == "__main__":
    sys.exit(main())
