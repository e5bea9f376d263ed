#!/usr/bin/env python3
"""Equal-time error of brume's integrators on one scene, against a converged reference.

For each integrator named (path, bdpt, ...) the scene is rendered for the
same wall-clock budget (`brume render --time SECONDS`, a different seed
than the reference) and compared with the reference by `brume compare`.
Each render gets `--set integrator.type=NAME`, so the scene file's own
choice never leaks into another integrator's row. The reference is one long render of REF_INTEGRATOR made as two sample
ranges (`--samples`), merged by `brume merge`; the difference of its halves
estimates its own noise, which is subtracted from each run's squared error.

    python3 tools/equal_time.py scenes/mirror_beam.toml --integrators path,bdpt \\
        --seconds 20 --reference-spp 4096 --reference-integrator bdpt --repeats 3

An integrator name ending in `+guiding` or `-guiding` also sets
`integrator.guiding` (path guiding on or off) for its renders.

Prints a Markdown table: integrator, samples per pixel reached, seconds,
RMSE (reference noise removed), efficiency 1 / (MSE · seconds), each the
median over `--repeats` seeds (efficiency with its min–max), and the
efficiency relative to the first integrator. Only the Python standard
library and the brume binary are needed (BRUME, default target/release/brume).
Renders run one at a time under the CPU lock (BRUME_CPU_LOCK, default
/tmp/cpu.lock) so that they never share the machine's cores.
"""

import argparse
import fcntl
import hashlib
import math
import os
import re
import subprocess
import statistics
import sys
from contextlib import contextmanager
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
BRUME = Path(os.environ.get("BRUME", REPO / "target" / "release" / "brume"))
LOCK = os.environ.get("BRUME_CPU_LOCK", "/tmp/cpu.lock")
CACHE = Path(os.environ.get("BRUME_EQUAL_TIME_CACHE", Path.home() / ".cache" / "brume-equal-time"))
RATE_RE = re.compile(r"at (\d+) spp in ([0-9.]+) s")
RMSE_RE = re.compile(r"^rmse\s+(\S+)", re.M)


@contextmanager
def cpu_lock():
    with open(LOCK, "a") as f:
        fcntl.flock(f, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(f, fcntl.LOCK_UN)


def integrator_flag(integrator: str) -> list:
    """The `--set` that makes a render use `integrator`, whatever the scene file says.

    `NAME+guiding` / `NAME-guiding` also switch path guiding on / off
    (`integrator.guiding`), e.g. `--integrators path-guiding,path+guiding`."""
    for suffix, value in (("+guiding", "true"), ("-guiding", "false")):
        if integrator.endswith(suffix):
            name = integrator[: -len(suffix)]
            return ["--set", f'integrator.type="{name}"', "--set", f"integrator.guiding={value}"]
    return ["--set", f'integrator.type="{integrator}"']


def run(cmd):
    r = subprocess.run([str(c) for c in cmd], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"{' '.join(map(str, cmd))} failed ({r.returncode}):\n{r.stderr[-2000:]}")
    return r


def render(scene, out, *flags):
    with cpu_lock():
        r = run([BRUME, "render", scene, "--out", out, "--png", out.with_suffix(".png"), *flags])
    m = RATE_RE.search(r.stderr)
    if not m:
        sys.exit(f"no 'at N spp in S s' summary in brume's output:\n{r.stderr[-2000:]}")
    return int(m.group(1)), float(m.group(2))


def rmse(a, b):
    r = run([BRUME, "compare", a, b])
    return float(RMSE_RE.search(r.stdout).group(1))


def reference(scene, args):
    """(reference EXR, variance of its error): cached by scene text and settings."""
    key = hashlib.sha256(
        (scene.read_text() + f"{args.reference_spp} {args.reference_integrator}").encode()
    ).hexdigest()[:16]
    ref = CACHE / f"{scene.stem}-{key}.exr"
    halves = [CACHE / f"{scene.stem}-{key}-{i}.exr" for i in (0, 1)]
    if not ref.exists():
        CACHE.mkdir(parents=True, exist_ok=True)
        n = args.reference_spp
        for i, (lo, hi) in enumerate([(0, n // 2), (n // 2, n)]):
            spp, secs = render(scene, halves[i], *integrator_flag(args.reference_integrator),
                               "--spp", n, "--samples", f"{lo}..{hi}")
            print(f"reference half {i}: samples {lo}..{hi} in {secs:.1f} s", file=sys.stderr)
        run([BRUME, "merge", *halves, "-o", ref, "--png", ref.with_suffix(".png")])
    # ref = (a + b) / 2, so var(ref) = E[(a - b)^2] / 4.
    return ref, rmse(halves[0], halves[1]) ** 2 / 4


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("scene", type=Path)
    p.add_argument("--integrators", default="path,bdpt")
    p.add_argument("--seconds", type=float, default=20.0)
    p.add_argument("--reference-spp", type=int, default=4096)
    p.add_argument("--reference-integrator", default="path")
    p.add_argument("--seed", type=int, default=12345)
    p.add_argument("--repeats", type=int, default=1,
                   help="runs per integrator (seeds SEED, SEED+1, ...); the table shows medians")
    p.add_argument("--work", type=Path, default=CACHE / "runs")
    args = p.parse_args()
    args.work.mkdir(parents=True, exist_ok=True)
    scene = args.scene.resolve()
    ref, ref_var = reference(scene, args)
    rows = []
    for name in args.integrators.split(","):
        runs = []
        for r in range(args.repeats):
            out = args.work / f"{scene.stem}-{name}-{r}.exr"
            spp, secs = render(scene, out, *integrator_flag(name),
                               "--time", args.seconds, "--seed", args.seed + r)
            mse = max(rmse(out, ref) ** 2 - ref_var, 1e-30)
            runs.append((spp, secs, mse, 1.0 / (mse * secs)))
        rows.append((name, *(statistics.median(x) for x in zip(*runs)),
                     min(x[3] for x in runs), max(x[3] for x in runs)))
    print(f"Scene `{args.scene}`, {args.seconds:g} s each, median of {args.repeats} run(s);"
          f" reference: {args.reference_integrator}, {args.reference_spp} spp"
          f" (its own RMSE {math.sqrt(ref_var):.3g}, removed).\n")
    print("| integrator | spp | seconds | RMSE | efficiency 1/(MSE·s) (min–max) | relative |")
    print("| --- | ---: | ---: | ---: | ---: | ---: |")
    for name, spp, secs, mse, eff, lo, hi in rows:
        print(f"| {name} | {spp:g} | {secs:.1f} | {math.sqrt(mse):.4g} | {eff:.4g} ({lo:.4g}–{hi:.4g})"
              f" | {eff / rows[0][4]:.2f}× |")


if __name__ == "__main__":
    main()
