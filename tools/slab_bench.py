#!/usr/bin/env python3
"""The light-slab section of the benchmark report (issue 34).

The plume of scenes/smoke.toml (its sun and sky, without its ground) is baked
into light slabs over a grid of spatial x angular resolutions; each slab is
viewed from a novel camera (behind and above the plume, a view the bake
never used) and compared with path tracing that view: RMSE, relative error
of the image mean, file size, bake time and view time. Then a 64-frame
orbit around the slab's box, rendered as a user would: one
`brume render --frames` process whose camera is keyframed around the box
(`animation.keyframe_time = "absolute"`), every frame from the slab, and
path traced at 256 spp the same way (all frames, or every Nth frame and the
total scaled), and the ratio of their wall times; the slab orbit is also
timed as one process per frame. Optionally the turntable contact sheets for
docs/gallery.md.

    python3 tools/slab_bench.py --markdown /tmp/slab_bench/section.md \\
        --plot docs/slab_error.png --sheet docs/slab_turntable.png

`--orbit-only SLAB` skips the reference and the grid and times the orbit
from an already baked slab (the spatial/angular of --orbit-spatial and
--orbit-angular, for the text).

Every bake, render and timing runs under the shared CPU lock
(BRUME_CPU_LOCK, default /tmp/cpu.lock), taken once for the grid and once
for the orbit, so a timing excludes the wait for the lock. Do not run the script itself under flock on
the same file (it would wait for itself). Needs target/release/brume and
the contact_sheet example built (cargo build --release --bin brume
--example contact_sheet); matplotlib for the plot.
"""

import argparse
import fcntl
import math
import os
import re
import subprocess
import sys
import time
from contextlib import contextmanager
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
BRUME = ROOT / "target" / "release" / "brume"
SHEET = ROOT / "target" / "release" / "examples" / "contact_sheet"
LOCK = os.environ.get("BRUME_CPU_LOCK", "/tmp/cpu.lock")
BOX = ([-0.75, 0.0, -0.72], [0.74, 1.92, 0.72])
LOOK_AT = [0.0, 0.9, 0.0]
NOVEL_EYE = [1.2, 2.9, -3.4]
ORBIT_RADIUS = 4.2
ORBIT_HEIGHT = 1.8

LIGHTS_AND_PLUME = """
[integrator]
max_depth = 32
[[light]]
type = "sun"
direction = [-1.0, -1.1, -0.7]
irradiance = [3.0, 2.85, 2.6]
[[light]]
type = "sky"
zenith = [0.25, 0.4, 0.8]
horizon = [0.6, 0.7, 0.8]
ground = [0.1, 0.1, 0.1]
"""

MEDIUM = """
[[medium]]
type = "vdb"
file = "{vdb}"
grid = "density"
density_scale = 20.0
albedo = [0.9, 0.9, 0.9]
phase = {{ type = "hg", g = 0.3 }}
transform = {{ translate = [-1.02, 0.0, -1.0] }}
"""


def camera(eye, size):
    """A [camera] table looking at the plume from `eye`, `size` pixels square."""
    return (f"[camera]\nposition = {list(eye)}\nlook_at = {LOOK_AT}\n"
            f"fov = 40.0\nresolution = [{size}, {size}]\n")


def traced_scene(eye, size):
    """The plume path traced (smoke.toml without its ground)."""
    vdb = ROOT / "volumes" / "smoke_plume.vdb"
    return camera(eye, size) + LIGHTS_AND_PLUME + MEDIUM.format(vdb=vdb)


def bake_scene(spatial, angular):
    """The plume with the README's [slab] box at a resolution."""
    lo, hi = BOX
    return (traced_scene(NOVEL_EYE, 64)
            + f"[slab]\nmin = {lo}\nmax = {hi}\nspatial = {spatial}\nangular = {angular}\n")


def view_scene(slab, eye, size):
    """The same sun and sky looking at a baked slab instead of the medium."""
    return (camera(eye, size) + LIGHTS_AND_PLUME
            + f'[[shape]]\ntype = "slab"\nfile = "{slab}"\n')


@contextmanager
def cpu_lock():
    """The shared CPU lock, held for one command."""
    with open(LOCK, "a") as f:
        fcntl.flock(f, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(f, fcntl.LOCK_UN)


def run(cmd):
    """Runs `cmd` (the caller holds the CPU lock); its wall seconds."""
    t0 = time.perf_counter()
    p = subprocess.run([str(c) for c in cmd], capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if p.returncode != 0:
        sys.exit(f"{' '.join(map(str, cmd))} failed ({p.returncode}):\n{p.stderr[-2000:]}")
    return wall


def render(scene_text, path, spp, extra=()):
    """Writes the scene beside `path` (an .exr) and renders it; wall seconds."""
    toml = path.with_suffix(".toml")
    toml.write_text(scene_text)
    return run([BRUME, "render", "--quiet", toml, "--out", path, "--spp", spp, *extra])


def compare(image, reference):
    """brume compare: RMSE and the grey means of both images."""
    p = subprocess.run([str(BRUME), "compare", str(image), str(reference)],
                       capture_output=True, text=True, check=True)
    rmse = float(re.search(r"rmse\s+(\S+)", p.stdout).group(1))
    means = [sum(map(float, m.split())) / 3 for m in
             re.findall(r"mean [AB] \(R G B\)\s+(.+)", p.stdout)]
    return rmse, means[0], means[1]


def reference(work, spp):
    """The novel view path traced in two independent halves, merged; its noise."""
    halves = []
    seconds = 0.0
    for i in range(2):
        half = work / f"ref_half{i}.exr"
        samples = f"{i * spp // 2}..{(i + 1) * spp // 2}"
        seconds += render(traced_scene(NOVEL_EYE, 256), half, spp, ["--samples", samples])
        halves.append(half)
    ref = work / "ref.exr"
    run([BRUME, "merge", "--out", ref, *halves])
    # Two independent halves: RMSE(A, B) / 2 is the RMSE of their average.
    noise = compare(halves[0], halves[1])[0] / 2
    return ref, noise, seconds


def grid_cell(work, ref, spatial, angular, args):
    """Bakes one resolution, views it and scores the view against `ref`."""
    name = f"s{spatial}_a{angular}"
    bake = work / f"{name}.toml"
    bake.write_text(bake_scene(spatial, angular))
    slab = work / f"{name}.slab"
    bake_s = run([BRUME, "slab", "bake", "--quiet", bake, "--out", slab,
                  "--spp", args.bake_spp])
    view = work / f"{name}_view.exr"
    view_s = render(view_scene(slab, NOVEL_EYE, 256), view, args.view_spp)
    rmse, mean, ref_mean = compare(view, ref)
    return {"spatial": spatial, "angular": angular, "rmse": rmse,
            "mean_error": mean / ref_mean - 1, "bytes": slab.stat().st_size,
            "bake_s": bake_s, "view_s": view_s, "slab": slab}


def orbit_eye(i, frames):
    """Frame i's camera on the circle around the box."""
    a = 2 * math.pi * i / frames
    return [round(ORBIT_RADIUS * math.sin(a), 5), ORBIT_HEIGHT,
            round(ORBIT_RADIUS * math.cos(a), 5)]


def orbit_camera(frames, size):
    """The [camera] of the orbit: frame 0's eye turned about +y by quarter
    turns keyed at frame numbers, so frame i is at orbit_eye(i, frames)."""
    keys = ",\n".join(
        f"    {{ time = {k * frames / 4}, rotate = [0.0, {90 * k}.0, 0.0] }}" for k in range(5))
    return (camera(orbit_eye(0, frames), size)
            + f"transform = {{ keyframes = [\n{keys},\n] }}\n")


def orbit_sequence(text, frames, out, args, spp):
    """Renders `text` (a scene without camera) along the orbit in one
    `brume render --frames` process, frames `frames` (a --frames list);
    wall seconds."""
    toml = out.with_suffix(".toml")
    toml.write_text(orbit_camera(args.frames, args.orbit_size) + text
                    + '[animation]\nkeyframe_time = "absolute"\n')
    return run([BRUME, "render", "--quiet", toml, "--frames", frames,
                "--out", f"{out}####.exr", "--png", f"{out}####.png", "--spp", spp])


def orbit(work, slab, args):
    """The orbit from the slab (every frame) and path traced (every Nth),
    each in one process; the slab also one process per frame. Timed."""
    out = work / "orbit"
    out.mkdir(exist_ok=True)
    slab_body = LIGHTS_AND_PLUME + f'[[shape]]\ntype = "slab"\nfile = "{slab}"\n'
    traced_body = LIGHTS_AND_PLUME + MEDIUM.format(vdb=ROOT / "volumes" / "smoke_plume.vdb")
    slab_s = orbit_sequence(slab_body, f"0-{args.frames - 1}", out / "slab", args,
                            args.view_spp)
    per_process_s = 0.0
    for i in range(args.frames):
        eye = orbit_eye(i, args.frames)
        per_process_s += render(view_scene(slab, eye, args.orbit_size),
                                out / f"process{i:04}.exr", args.view_spp)
    traced = list(range(0, args.frames, args.traced_every))
    traced_s = orbit_sequence(traced_body, f"0-{args.frames - 1}:{args.traced_every}",
                              out / "traced", args, args.traced_spp)
    errors = []
    for i in traced:
        rmse, mean, ref_mean = compare(out / f"slab{i:04}.exr", out / f"traced{i:04}.exr")
        errors.append((rmse, mean / ref_mean - 1))
    # The keyed orbit is the per-process orbit up to f32 rounding of the rotation.
    keyed_vs_placed = max(compare(out / f"slab{i:04}.exr", out / f"process{i:04}.exr")[0]
                          for i in traced)
    scaled = traced_s * args.frames / len(traced)
    return {"slab_s": slab_s, "per_process_s": per_process_s, "traced_s": traced_s,
            "traced_n": len(traced), "traced_total": scaled, "ratio": scaled / slab_s,
            "per_process_ratio": scaled / per_process_s, "errors": errors,
            "keyed_vs_placed": keyed_vs_placed, "dir": out}


def plot(rows, path):
    """RMSE against spatial resolution, one line per angular resolution."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(5.5, 3.6), dpi=100)
    for angular in sorted({r["angular"] for r in rows}):
        pts = sorted((r["spatial"], r["rmse"]) for r in rows if r["angular"] == angular)
        ax.plot(*zip(*pts), marker="o", label=f"angular {angular}")
    ax.set_xlabel("spatial resolution (nodes per position axis)")
    ax.set_ylabel("RMSE vs path traced (256², novel view)")
    ax.set_yscale("log")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(path)


def sheets(result, path, every):
    """Contact sheets of the orbit's slab frames (and their traced twins)."""
    d = result["dir"]
    frames = sorted(d.glob("traced*.exr"))[::max(1, every)]
    slab = [d / f.name.replace("traced", "slab") for f in frames]
    run([SHEET, 8, path, *slab])
    run([SHEET, 8, path.with_name(path.stem + "_traced.png"), *frames])


def grid_table(rows, ref_noise, ref_s, args):
    """The markdown table of the resolution grid."""
    lines = [
        f"Novel view 256², slab viewed at {args.view_spp} spp (quadrilinear), baked at "
        f"{args.bake_spp} spp per line; reference path traced at {args.ref_spp} spp "
        f"({ref_s:.1f} s; its own noise RMSE {ref_noise:.4f}, included in the RMSEs).",
        "",
        "| spatial | angular | lines | file | bake | view | RMSE | mean error |",
        "| ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |",
    ]
    for r in rows:
        lines_n = 6 * r["spatial"] ** 2 * r["angular"] ** 2
        lines.append(
            f"| {r['spatial']} | {r['angular']} | {lines_n / 1e6:.3f} M | "
            f"{r['bytes'] / 1e6:.1f} MB | {r['bake_s']:.2f} s | {r['view_s']:.2f} s | "
            f"{r['rmse']:.4f} | {100 * r['mean_error']:+.2f} % |")
    return lines


def orbit_lines(o, args):
    """The markdown lines of the orbit timing."""
    rmse = sum(e[0] for e in o["errors"]) / len(o["errors"])
    worst = max(abs(e[1]) for e in o["errors"])
    scaled = ("" if o["traced_n"] == args.frames else
              f" ({o['traced_n']} evenly spaced frames, every {args.traced_every}th, "
              f"took {o['traced_s']:.1f} s; scaled by {args.frames}/{o['traced_n']})")
    seq = "one `brume render --frames` (keyframed camera)"
    return [
        "",
        f"Orbit: {args.frames} frames at {args.orbit_size}², radius {ORBIT_RADIUS} m, "
        f"height {ORBIT_HEIGHT} m, from the spatial {args.orbit_spatial} x "
        f"angular {args.orbit_angular} slab; wall time of whole `brume` processes "
        f"(start-up, scene and slab or VDB load, EXR and PNG writing included):",
        "",
        "| | how | frames | spp | wall time |",
        "| --- | --- | ---: | ---: | ---: |",
        f"| slab | {seq} | {args.frames} | {args.view_spp} | {o['slab_s']:.2f} s |",
        f"| slab | one `brume render` per frame | {args.frames} | {args.view_spp} | "
        f"{o['per_process_s']:.2f} s |",
        f"| path traced | {seq} | {args.frames} | {args.traced_spp} | "
        f"{o['traced_total']:.1f} s{scaled} |",
        "",
        f"Ratio, both orbits in one process: **{o['ratio']:.0f}×** (goal ≥ 100×); "
        f"the slab at one process per frame against the same path-traced time: "
        f"{o['per_process_ratio']:.0f}×. Slab vs path traced over the traced frames: "
        f"mean RMSE {rmse:.4f}, worst image-mean error {100 * worst:.1f} %; the keyed "
        f"orbit vs the per-frame placed cameras: RMSE at most {o['keyed_vs_placed']:.1e}.",
    ]


def parse_args():
    """The harness's flags."""
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--work", type=Path, default=Path("/tmp/slab_bench"))
    p.add_argument("--spatial", default="16,32,48")
    p.add_argument("--angular", default="4,8,12")
    p.add_argument("--bake-spp", type=int, default=16)
    p.add_argument("--view-spp", type=int, default=4)
    p.add_argument("--ref-spp", type=int, default=1024)
    p.add_argument("--frames", type=int, default=64)
    p.add_argument("--orbit-size", type=int, default=128)
    p.add_argument("--traced-spp", type=int, default=256)
    p.add_argument("--traced-every", type=int, default=4)
    p.add_argument("--orbit-spatial", type=int, default=48)
    p.add_argument("--orbit-angular", type=int, default=12)
    p.add_argument("--markdown", type=Path)
    p.add_argument("--plot", type=Path)
    p.add_argument("--sheet", type=Path)
    p.add_argument("--sheet-every", type=int, default=1,
                   help="take every Nth traced frame's pair for the sheets")
    p.add_argument("--orbit-only", type=Path, metavar="SLAB",
                   help="skip the reference and the grid: time the orbit from this baked slab")
    return p.parse_args()


def main():
    """Grid, orbit, table, plot, sheets."""
    args = parse_args()
    args.work.mkdir(parents=True, exist_ok=True)
    if args.orbit_only:
        with cpu_lock():
            o = orbit(args.work, args.orbit_only.resolve(), args)
        text = "\n".join(orbit_lines(o, args)) + "\n"
        print(text)
        if args.markdown:
            args.markdown.write_text(text)
        return
    with cpu_lock():
        ref, ref_noise, ref_s = reference(args.work, args.ref_spp)
        rows = []
        for s in map(int, args.spatial.split(",")):
            for a in map(int, args.angular.split(",")):
                rows.append(grid_cell(args.work, ref, s, a, args))
                print(rows[-1], file=sys.stderr)
    cell = [r for r in rows if (r["spatial"], r["angular"]) ==
            (args.orbit_spatial, args.orbit_angular)]
    with cpu_lock():
        slab = cell[0]["slab"] if cell else grid_cell(
            args.work, ref, args.orbit_spatial, args.orbit_angular, args)["slab"]
        o = orbit(args.work, slab, args)
    text = "\n".join(grid_table(rows, ref_noise, ref_s, args) + orbit_lines(o, args)) + "\n"
    print(text)
    if args.markdown:
        args.markdown.write_text(text)
    if args.plot:
        plot(rows, args.plot)
    if args.sheet:
        with cpu_lock():
            sheets(o, args.sheet, args.sheet_every)


if __name__ == "__main__":
    main()
