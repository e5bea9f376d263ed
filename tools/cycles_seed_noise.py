#!/usr/bin/env python3
"""Noise per sample of Blender Cycles on a harness scene, measured between two seeds.

The Cycles counterpart of tools/seed_noise.py: renders the tools/bench.py
scene KEY (B1, B3, CLOUD, ...) with Cycles (bpy 5.0.1, through
tools/cycles_bench.py's worker, the harness's settings) at SPP samples per
pixel, seeds 1 and 2, 2 threads, with the depth limit DEPTH in brume's
count (scattering events: Cycles gets DEPTH - 1 bounces, which gives the
same image mean as `brume render --set integrator.max_depth=DEPTH`), and
prints the image mean and the relative noise per sample (RMS difference /
sqrt(2) x sqrt(SPP) / mean), so that the two renderers' noise can be
compared order by order of scattering:

    python3 tools/cycles_seed_noise.py B3 1 32 160,160
    python3 tools/seed_noise.py ~/.cache/brume-bench/cycles-work/B3-160x160.toml 32 \\
        --set integrator.max_depth=1
"""
import json
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import bench  # noqa: E402
import cycles_bench  # noqa: E402
from exr_numpy import read_rgb  # noqa: E402


def main():
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    key, depth, spp, resolution = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
    if key not in bench.SCENES:
        sys.exit(f"cycles_seed_noise.py: no scene {key!r} in tools/bench.py (have {', '.join(bench.SCENES)})")
    desc = json.loads(json.dumps(bench.SCENES[key]))
    # cycles_scene.build gives Cycles the table's max_depth - 1 bounces; Cycles' bounce 0
    # is the light sampled at the first scattering event, so that is brume's DEPTH events.
    desc["max_depth"] = depth
    images, seconds = [], []
    with tempfile.TemporaryDirectory() as tmp:
        spec = Path(tmp) / "spec.json"
        spec.write_text(json.dumps(desc))
        for seed in (1, 2):
            out = Path(tmp) / f"seed{seed}.exr"
            cmd = [sys.executable, str(Path(__file__).resolve().parent / "cycles_bench.py"),
                   "cycles-worker", "--spec", str(spec), "--out", str(out), "--spp", str(spp),
                   "--seconds", "0", "--threads", "2", "--seed", str(seed),
                   "--resolution", resolution]
            vdb = cycles_bench.vdb_path(key)
            if vdb:
                cmd += ["--vdb", vdb]
            run = subprocess.run(cmd, check=True, capture_output=True, text=True)
            seconds.append(json.loads(run.stdout.strip().splitlines()[-1])["seconds"])
            images.append(read_rgb(out).astype(np.float64))
    a, b = images
    mean = 0.5 * (a + b).mean()
    var = ((a - b) ** 2).mean() / 2
    print(f"cycles {key} max_depth {depth}: mean {mean:.5f}  noise per sample "
          f"{np.sqrt(var * spp) / mean:.4f}  render loop {np.median(seconds):.2f} s")


if __name__ == "__main__":
    main()
