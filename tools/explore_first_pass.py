"""The explorer's server alone: the time a fresh `pointshade explore SCENE` takes to answer its
page's first render request, a 1-spp pass (`POST /api/render?spp=1` of the session's state; with
`--spp N` an N-spp pass, with `--spp 0` the film's own), with no browser on the same cores.
docs/explore.md compares it with what the browser test sees.

    python3 tools/explore_first_pass.py [SCENE] [--spp N] [--repeats N]   (after `cargo build --release`)
"""

import argparse
import json
import statistics
import subprocess
import time
import urllib.request
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def first_pass_ms(cli, scene, spp):
    process = subprocess.Popen([cli, "explore", str(scene), "--port", "0"], stdout=subprocess.PIPE, text=True)
    try:
        url = process.stdout.readline().strip()
        if not url.startswith("http://127.0.0.1:"):
            raise SystemExit(f"error: pointshade explore {scene} did not start (printed {url!r})")
        with urllib.request.urlopen(url + "api/session") as reply:
            state = json.load(reply)["state"]
        path = "api/render" if spp == 0 else f"api/render?spp={spp}"
        request = urllib.request.Request(url + path, data=json.dumps(state).encode(), method="POST")
        start = time.perf_counter()
        with urllib.request.urlopen(request) as reply:
            reply.read()
        return 1000 * (time.perf_counter() - start)
    finally:
        process.terminate()
        process.wait()


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene", nargs="?", default=ROOT / "scenes/shared/dragon-copper.toml")
    parser.add_argument("--spp", type=int, default=1, help="the pass's samples per pixel (0: the film's)")
    parser.add_argument("--repeats", type=int, default=6)
    parser.add_argument("--cli", default=str(ROOT / "target/release/pointshade"))
    args = parser.parse_args()
    times = [first_pass_ms(args.cli, args.scene, args.spp) for _ in range(args.repeats)]
    what = "the film's pass" if args.spp == 0 else f"a {args.spp}-spp pass"
    print(f"first render, {what}, of {args.scene}: median {statistics.median(times):.1f} ms "
          f"(min {min(times):.1f}, max {max(times):.1f}, n = {len(times)})")


if __name__ == "__main__":
    main()
