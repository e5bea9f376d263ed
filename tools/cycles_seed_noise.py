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
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import bench  # noqa: E402
import cycles_bench  # noqa: E402
from seed_noise import noise_per_sample  # noqa: E402


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
    res = [int(x) for x in resolution.split(",")]
    with tempfile.TemporaryDirectory() as tmp:
        runs = [cycles_bench.run_cycles(key, res, spp, 2, seed, (False, False), Path(tmp), desc=desc)
                for seed in (1, 2)]
    a, b = (r["image"].astype(np.float64) for r in runs)
    mean, noise = noise_per_sample(a, b, spp)
    seconds = np.median([r["seconds"] for r in runs])
    print(f"cycles {key} max_depth {depth}: mean {mean:.5f}  noise per sample {noise:.4f}  "
          f"render loop {seconds:.2f} s")


if __name__ == "__main__":
    main()
