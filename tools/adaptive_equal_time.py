#!/usr/bin/env python3
"""Equal-time error of brume with `--adaptive off` against its default
(the automatic choice) or `--adaptive on`, against a converged reference.

    python3 tools/adaptive_equal_time.py SCENE.toml REFERENCE.npz \
        [--seconds 4] [--seeds 1,2,3] [--modes off,auto] [--brume target/release/brume]
        [--variant NAME='FLAGS' ...]

REFERENCE.npz holds two independently seeded halves `a` and `b` of the
reference image (height × width × 3), as tools/bench.py and
tools/cycles_bench.py cache them in ~/.cache/brume-bench/references; their
own noise is subtracted from each MSE. Each render takes the CPU lock
(`flock /tmp/cpu.lock`, or $BRUME_CPU_LOCK) and `--time SECONDS`;
efficiency = 1 / (MSE × seconds), with the seconds brume reports. Prints
one line per render and the median efficiency of each mode over the seeds.
Each `--variant NAME='FLAGS'` (repeatable) replaces the modes with a render
given those flags, e.g. `--variant collision='--adaptive off --set
integrator.forced_scattering=false'`.
"""

import argparse
import os
import re
import shlex
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from exr_numpy import read_rgb  # noqa: E402

RATE_RE = re.compile(r"at (\d+) spp in ([0-9.]+) s")


def render(brume, scene, flags, seed, seconds, out, lock):
    cmd = ["flock", lock, brume, "render", scene, "--threads", "2", "--seed", str(seed),
           "--time", str(seconds), *flags, "--out", str(out), "--png", str(out.with_suffix(".png"))]
    p = subprocess.run(cmd, capture_output=True, text=True)
    m = RATE_RE.search(p.stderr)
    if p.returncode != 0 or not m:
        sys.exit(f"brume failed ({p.returncode}):\n{p.stderr}")
    chosen = [l for l in p.stderr.splitlines() if "automatic" in l or l.startswith("adaptive:")]
    return float(m.group(2)), chosen


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scene")
    ap.add_argument("reference")
    ap.add_argument("--seconds", type=float, default=4.0)
    ap.add_argument("--seeds", default="1,2,3")
    ap.add_argument("--modes", default="off,auto", help="comma-separated: off, on, auto (no flag)")
    ap.add_argument("--variant", action="append", default=[],
                    help="NAME=FLAGS: a render with these flags (replaces --modes)")
    ap.add_argument("--brume", default=str(Path(__file__).resolve().parents[1] / "target/release/brume"))
    args = ap.parse_args()
    lock = os.environ.get("BRUME_CPU_LOCK", "/tmp/cpu.lock")
    ref = np.load(args.reference)
    a, b = ref["a"], ref["b"]
    mean_ref = (a + b) / 2
    ref_var = float(np.mean((a - b) ** 2)) / 4
    efficiency = {}
    with tempfile.TemporaryDirectory() as tmp:
        if args.variant:
            variants = [(v.split("=", 1)[0], shlex.split(v.split("=", 1)[1])) for v in args.variant]
        else:
            variants = [(m, [] if m == "auto" else ["--adaptive", m]) for m in args.modes.split(",")]
        for mode, flags in variants:
            for seed in [int(s) for s in args.seeds.split(",")]:
                out = Path(tmp) / f"{mode}-{seed}.exr"
                seconds, chosen = render(args.brume, args.scene, flags, seed, args.seconds, out, lock)
                mse = float(np.mean((read_rgb(out) - mean_ref) ** 2)) - ref_var
                eff = 1.0 / (mse * seconds)
                efficiency.setdefault(mode, []).append(eff)
                print(f"{mode} seed {seed}: {seconds:.2f} s, MSE {mse:.4g}, efficiency {eff:.4g}"
                      + "".join(f"\n    {c}" for c in chosen), flush=True)
    base = statistics.median(next(iter(efficiency.values())))
    for mode, effs in efficiency.items():
        med = statistics.median(effs)
        print(f"{mode}: median efficiency {med:.4g} ({med / base:.2f}x the first mode)")


if __name__ == "__main__":
    main()
