#!/usr/bin/env python3
"""Efficiency of two or more brume binaries on one scene, as the Cycles
harness runs brume (its defaults, the scene's spp), against a converged
reference.

    python3 tools/compare_binaries.py SCENE.toml REFERENCE.npz \
        --seeds 1,2,3 BRUME_A BRUME_B [...]

REFERENCE.npz holds two independently seeded halves `a` and `b` of the
reference (height × width × 3), as tools/cycles_bench.py caches them in
~/.cache/brume-bench/references (scenes in ~/.cache/brume-bench/cycles-work);
their own noise is subtracted from each MSE. Each render takes the CPU lock
(`flock /tmp/cpu.lock`, or $BRUME_CPU_LOCK), the binaries interleaved seed
by seed; efficiency = 1 / (MSE × seconds), with the render seconds brume
reports. Prints one line per render, then each binary's median efficiency
and its ratio to the first binary's.
"""

import argparse
import os
import re
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from exr_numpy import read_rgb  # noqa: E402

RATE_RE = re.compile(r"at (\d+) spp in ([0-9.]+) s")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scene")
    ap.add_argument("reference")
    ap.add_argument("binaries", nargs="+")
    ap.add_argument("--seeds", default="1,2,3")
    ap.add_argument("--threads", type=int, default=2)
    a = ap.parse_args()
    lock = os.environ.get("BRUME_CPU_LOCK", "/tmp/cpu.lock")
    ref = np.load(a.reference)
    half_a, half_b = ref["a"].astype(np.float64), ref["b"].astype(np.float64)
    truth = 0.5 * (half_a + half_b)
    ref_noise = ((half_a - half_b) ** 2).mean() / 4.0
    efficiency = {b: [] for b in a.binaries}
    with tempfile.TemporaryDirectory() as tmp:
        out = str(Path(tmp) / "image.exr")
        for seed in [int(s) for s in a.seeds.split(",")]:
            for brume in a.binaries:
                cmd = ["flock", lock, brume, "render", a.scene, "--threads", str(a.threads),
                       "--seed", str(seed), "--out", out]
                run = subprocess.run(cmd, capture_output=True, text=True, check=True)
                m = RATE_RE.search(run.stderr)
                if not m:
                    sys.exit(f"no timing in brume's output:\n{run.stderr}")
                seconds = float(m.group(2))
                mse = ((read_rgb(out).astype(np.float64) - truth) ** 2).mean() - ref_noise
                efficiency[brume].append(1.0 / (mse * seconds))
                print(f"{brume} seed {seed}: {m.group(1)} spp, {seconds:.2f} s, MSE {mse:.4g}, "
                      f"efficiency {efficiency[brume][-1]:.1f}", flush=True)
    base = statistics.median(efficiency[a.binaries[0]])
    for brume in a.binaries:
        med = statistics.median(efficiency[brume])
        print(f"{brume}: median efficiency {med:.1f}, {med / base:.3f}× the first")


if __name__ == "__main__":
    main()
