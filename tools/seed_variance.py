"""Error per sample of a brume build, without a reference: renders a scene
once per seed and averages the per-pixel variance across the seeds.

    python3 tools/seed_variance.py BRUME SCENE SPP SEEDS [extra render options]

Prints the image mean, the mean per-pixel variance of one SPP-sample image
("image MSE") and its square root over the mean. Two builds compared at the
same SPP differ in error per sample by the ratio of their image MSEs. Reads
EXR through Mitsuba's Bitmap, as tools/bench.py does.
"""
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench import read_exr  # noqa: E402


def main():
    if len(sys.argv) < 5:
        sys.exit(__doc__)
    binary, scene, spp, seeds = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])
    if seeds < 2:
        sys.exit("seed_variance.py: SEEDS must be at least 2")
    extra = sys.argv[5:]
    images = []
    with tempfile.TemporaryDirectory() as work:
        for seed in range(1, seeds + 1):
            exr = Path(work) / f"seed_{seed}.exr"
            subprocess.run([binary, "render", scene, "--spp", spp, "--seed", str(seed),
                            "--out", str(exr), "--png", str(Path(work) / "preview.png"), "-q",
                            *extra], check=True)
            images.append(read_exr(exr))
    stack = np.stack(images)
    mse = stack.var(axis=0, ddof=1).mean()
    print(f"mean {stack.mean():.5f}  image MSE {mse:.6e}  "
          f"relative noise {np.sqrt(mse) / stack.mean():.5f}")


if __name__ == "__main__":
    main()
