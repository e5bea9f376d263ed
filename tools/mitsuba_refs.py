#!/usr/bin/env python3
"""Render Mitsuba 3's own test scenes with brume and compare them with
Mitsuba's reference images (issue 37's held-out check).

    python3 tools/mitsuba_refs.py PATH/TO/mitsuba-data --brume target/release/brume

PATH/TO/mitsuba-data is your checkout of github.com/mitsuba-renderer/mitsuba-data
(its tests/scenes/*/*.xml and tests/scenes/*/refs/*_ref_rgb.exr are read, nothing
is written there). Each scene is rendered with the integrator its file name
ends with (`scene_volpath.xml` → `--set integrator=volpath`, as Mitsuba's
test_renders.py does), at the scene's own resolution, `--seeds` times with
`--spp` samples per pixel each. A scene brume refuses is listed with brume's
one-line reason.

The numbers:
- brume mean, ref mean: the image mean per channel (R G B);
- z of the mean: the largest over R, G, B of (brume − ref) / its standard
  error, which adds brume's (each pixel's variance over the seeds) and the
  reference's (its `_ref_rgb_var.exr` is the variance of ONE sample, from
  Mitsuba's `moment` integrator, so the reference's own error is that
  divided by its sample count, `--ref-spp`, 32000 by Mitsuba's script);
- |z|>3: the fraction of pixel channels whose difference exceeds 3 standard
  errors, brume's per-pixel variance pooled over 3×3 pixels (four seeds give
  too few degrees of freedom alone) plus the reference's; about 0.3 % if
  the two images estimate the same thing and the errors are normal, more
  with a variance estimated from few seeds and with the heavy tails of rare
  paths;
- verdict: agree when |z of the mean| < 3 and |z|>3 below twice the tail
  expected from Student's t with 9 (seeds − 1) degrees of freedom (brume's
  variance estimated from the seeds and 3×3 pixels): 3.0 % for two seeds,
  1.1 % for four.

Mitsuba writes its references with PIZ compression, which tools/exr_numpy.py
does not decode: install the `OpenEXR` Python package (pip install OpenEXR).
"""

import argparse
import glob
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import exr_numpy  # noqa: E402


def read_exr(path):
    """(height, width, 3) float32 RGB of an EXR: OpenEXR if installed, else exr_numpy."""
    try:
        import OpenEXR
    except ImportError:
        return exr_numpy.read_rgb(path)
    with OpenEXR.File(path) as f:
        channels = f.parts[0].channels
        if "RGB" in channels:
            return np.asarray(channels["RGB"].pixels, dtype=np.float32)
        return np.stack([np.asarray(channels[c].pixels, dtype=np.float32) for c in "RGB"], axis=-1)


def scenes(data):
    """(scene file, integrator, reference, reference variance) of every test scene."""
    out = []
    for xml in sorted(glob.glob(os.path.join(data, "tests", "scenes", "*", "*.xml"))):
        stem, integrator = os.path.splitext(os.path.basename(xml))[0].rsplit("_", 1)
        refs = os.path.join(os.path.dirname(xml), "refs")
        ref = os.path.join(refs, stem + "_ref_rgb.exr")
        out.append((xml, integrator, ref, ref.replace(".exr", "_var.exr")))
    return out


def local(message, xml):
    """`message` with files named from the scene's folder, not where the data sits."""
    return message.replace(os.path.dirname(os.path.abspath(xml)) + os.sep, "")


def refusal(brume, xml):
    """brume's one-line reason when it refuses the scene (`brume info` reads and builds it), else None."""
    # `info` takes no --set: the scene's own default integrator is read; the
    # render below sets the file name's and reports a refusal of it too.
    cmd = [brume, "info", os.path.basename(xml)]
    run = subprocess.run(cmd, cwd=os.path.dirname(xml), capture_output=True, text=True)
    if run.returncode == 0:
        return None
    lines = [l for l in run.stderr.splitlines() if l.startswith("error")] or [run.stderr.strip()]
    return f"exit {run.returncode}: {local(lines[-1], xml)}"


def render(brume, xml, integrator, spp, seed, work, reuse=False):
    """Renders one seed; returns (image or None, refusal line or None, seconds)."""
    name = os.path.splitext(os.path.basename(xml))[0]
    out = os.path.join(work, f"{name}_{seed}.exr")
    if reuse and os.path.exists(out):
        return read_exr(out), None, 0.0
    cmd = [brume, "render", os.path.basename(xml), "--set", f"integrator={integrator}",
           "--spp", str(spp), "--seed", str(seed), "--out", out,
           "--png", out.replace(".exr", ".png"), "-q"]
    start = time.time()
    # From the scene's folder, as Mitsuba resolves the scene's files.
    run = subprocess.run(cmd, cwd=os.path.dirname(xml), capture_output=True, text=True)
    seconds = time.time() - start
    if run.returncode != 0:
        lines = [l for l in run.stderr.splitlines() if l.startswith("error")] or [run.stderr.strip()]
        return None, f"exit {run.returncode}: {local(lines[-1], xml)}", seconds
    return read_exr(out), None, seconds


def pooled(var):
    """Per-pixel variance averaged over each pixel's 3×3 neighbourhood (edges replicated)."""
    padded = np.pad(var, ((1, 1), (1, 1), (0, 0)), mode="edge")
    h, w = var.shape[:2]
    return sum(padded[i:i + h, j:j + w] for i in range(3) for j in range(3)) / 9.0


def compare(images, ref, ref_var, ref_spp):
    """The statistics of the table for brume's seed images against the reference."""
    stack = np.stack(images)
    mean = stack.mean(axis=0)
    # The variance of brume's mean image, pixel by pixel, from the spread over seeds.
    var_mean = stack.var(axis=0, ddof=1) / len(images)
    var_ref = np.maximum(ref_var, 0.0) / ref_spp
    pixels = mean.shape[0] * mean.shape[1]
    diff_mean = mean.mean(axis=(0, 1)) - ref.mean(axis=(0, 1))
    se_mean = np.sqrt((var_mean.sum(axis=(0, 1)) + var_ref.sum(axis=(0, 1))) / pixels**2)
    z_mean = diff_mean / np.maximum(se_mean, 1e-30)
    se = np.sqrt(pooled(var_mean) + var_ref)
    diff = mean - ref
    z = np.where(se > 0, diff / np.maximum(se, 1e-30), np.where(diff == 0, 0.0, np.inf))
    return {
        "brume": mean.mean(axis=(0, 1)),
        "ref": ref.mean(axis=(0, 1)),
        "z_mean": z_mean[np.argmax(np.abs(z_mean))],
        "frac3": float(np.mean(np.abs(z) > 3)),
    }


def t_tail(x, dof):
    """P(|T| > x) for Student's t with `dof` degrees of freedom (numerical integral of its density)."""
    import math
    c = math.exp(math.lgamma((dof + 1) / 2) - math.lgamma(dof / 2)) / math.sqrt(dof * math.pi)
    t = np.linspace(0.0, x, 20001)
    density = c * (1 + t * t / dof) ** (-(dof + 1) / 2)
    inside = float(np.sum((density[1:] + density[:-1]) / 2 * np.diff(t)))
    return 1.0 - 2.0 * inside


def rgb(v):
    """A colour as the table shows it."""
    return " ".join(f"{x:.4g}" for x in v)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("data", help="your checkout of mitsuba-data")
    parser.add_argument("--brume", required=True, help="the brume binary")
    parser.add_argument("--spp", type=int, default=256, help="samples per pixel of each seed")
    parser.add_argument("--seeds", type=int, default=4, help="renders per scene (seeds 1..N)")
    parser.add_argument("--ref-spp", type=float, default=32000,
                        help="samples per pixel of Mitsuba's references (its script's default)")
    parser.add_argument("--only", default="", help="only scenes whose path contains this")
    parser.add_argument("--work", help="folder for brume's images (default: a temporary one)")
    parser.add_argument("--reuse", action="store_true",
                        help="take the images already in --work instead of rendering them again")
    parser.add_argument("--mitsuba", metavar="VARIANT",
                        help="also render each scene brume accepts with the installed Mitsuba 3 "
                             "(e.g. llvm_ad_rgb), same spp and seeds, and judge it by the same "
                             "criterion: the baseline of what the criterion lets through")
    args = parser.parse_args()
    brume = os.path.abspath(args.brume)
    work = args.work or tempfile.mkdtemp(prefix="mitsuba_refs_")
    os.makedirs(work, exist_ok=True)
    # brume's per-pixel variance has 9 (seeds − 1) degrees of freedom (3×3
    # pooling): |z| > 3 is then a t tail, 1.5 % for two seeds, 0.6 % for four.
    limit = 2.0 * t_tail(3.0, 9 * (args.seeds - 1))
    extra = f" Mitsuba {args.mitsuba}: z, \\|z\\|>3 |" if args.mitsuba else ""
    print(f"| scene | spp | brume mean (RGB) | ref mean (RGB) | z of the mean | \\|z\\|>3 | verdict |{extra}")
    print("|---|---|---|---|---|---|---|" + ("---|" if args.mitsuba else ""))
    for xml, integrator, ref_path, var_path in scenes(args.data):
        name = os.path.relpath(xml, os.path.join(args.data, "tests", "scenes"))
        if args.only not in name:
            continue
        if not (os.path.exists(ref_path) and os.path.exists(var_path)):
            print(f"| {name} | | | | | | no rgb reference |", flush=True)
            continue
        refused = refusal(brume, xml)
        if refused:
            print(f"| {name} | | | | | | refused: {refused.replace('|', '/')} |", flush=True)
            continue
        images, seconds = [], 0.0
        for seed in range(1, args.seeds + 1):
            image, refused, took = render(brume, xml, integrator, args.spp, seed, work, args.reuse)
            seconds += took
            if refused:
                break
            images.append(image)
        if refused:
            print(f"| {name} | | | | | | refused: {refused.replace('|', '/')} |", flush=True)
            continue
        ref, ref_var = read_exr(ref_path), read_exr(var_path)
        s = compare(images, ref, ref_var, args.ref_spp)
        agree = abs(s["z_mean"]) < 3 and s["frac3"] < limit
        baseline = ""
        if args.mitsuba:
            own = mitsuba_images(args.mitsuba, xml, args.spp, args.seeds)
            m = compare(own, ref, ref_var, args.ref_spp)
            baseline = f" {m['z_mean']:+.1f}, {100 * m['frac3']:.2f} % |"
        print(f"| {name} | {args.seeds}×{args.spp} | {rgb(s['brume'])} | {rgb(s['ref'])} | "
              f"{s['z_mean']:+.1f} | {100 * s['frac3']:.2f} % | "
              f"{'agree' if agree else 'DISAGREE'} |{baseline}", flush=True)


def mitsuba_images(variant, xml, spp, seeds):
    """Mitsuba's own renders of `xml` (seeds 1..N) with the installed `mitsuba` module."""
    import mitsuba as mi
    mi.set_variant(variant)
    images = []
    for seed in range(1, seeds + 1):
        scene = mi.load_file(xml, spp=spp)
        images.append(np.array(mi.render(scene, spp=spp, seed=seed))[..., :3])
    return images


if __name__ == "__main__":
    main()
