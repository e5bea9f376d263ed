#!/usr/bin/env python3
"""Noise per sample of a brume render, measured between two seeds.

Renders SCENE twice (seeds 1 and 2, `--adaptive off`, SPP samples per pixel,
2 threads) with any extra `brume render` flags, and prints the image mean,
the relative noise per sample (RMS difference of the two images / sqrt(2)
x sqrt(SPP) / image mean: the per-sample standard deviation an unbiased
estimator would show, relative to the mean), the median render time and the
share of the variance held by the noisiest 0.1 %, 1 % and 10 % of pixels.
No reference image is needed, so it decomposes a scene's error by variant
(lights off, depth limits, estimator keys):

    python3 tools/seed_noise.py scenes/bench/b3_vdb_smoke.toml 16 --set integrator.max_depth=1
"""
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from exr_numpy import read_rgb  # noqa: E402


def noise_per_sample(a, b, spp):
    """Image mean and relative noise per sample of two renders of `spp` samples with other seeds."""
    mean = 0.5 * (a + b).mean()
    var = ((a - b) ** 2).mean() / 2
    return mean, np.sqrt(var * spp) / mean


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    scene, spp, extra = sys.argv[1], sys.argv[2], sys.argv[3:]
    brume = os.environ.get("BRUME", "target/release/brume")
    images, times = [], []
    with tempfile.TemporaryDirectory() as tmp:
        for seed in (1, 2):
            out = os.path.join(tmp, f"seed{seed}.exr")
            start = time.time()
            subprocess.run([brume, "render", scene, "--out", out, "--spp", spp,
                            "--seed", str(seed), "--adaptive", "off", "--threads", "2",
                            "--quiet"] + extra, check=True)
            times.append(time.time() - start)
            images.append(read_rgb(out).astype(np.float64))
    a, b = images
    mean, noise = noise_per_sample(a, b, int(spp))
    print(f"mean {mean:.5f}  noise per sample {noise:.4f}  time {np.median(times):.2f} s")
    d = np.sort(((a - b) ** 2).sum(axis=2).ravel())
    shares = [d[-max(1, len(d) // k):].sum() / d.sum() for k in (1000, 100, 10)]
    print("share of the variance in the noisiest 0.1 % / 1 % / 10 % of pixels: "
          + " ".join(f"{s:.2f}" for s in shares))


if __name__ == "__main__":
    main()
