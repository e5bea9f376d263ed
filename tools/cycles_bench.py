#!/usr/bin/env python3
"""brume beside Blender Cycles (bpy 5.0.1) at equal time (issue 35).

Scenes are described once, in tools/bench.py's parameter table format:
the smoke plume (bench B3) and the homogeneous fog cube (B1) come from that
table; the dense bright cloud, the diffuse ground under a uniform sky and
under scenes/sky.exr, and variants of the smoke (denser; lit from behind)
and of the cloud (lit from behind) that no tuning used, as checks on the
held-out goal, are defined here in the same format (CYCLES_EXTRA). brume's scene files are written by bench.py's
`brume_toml`, Cycles' scenes by tools/cycles_scene.py (a bpy worker process
per render, so Cycles' memory and threads are its own).

    python3 tools/cycles_bench.py run --markdown BENCHMARKS.md [options]

For each scene: a converged brume reference (two independently seeded halves,
cached in ~/.cache/brume-bench) and a long Cycles render (two halves) whose
means must agree with it (the match check: mean ratio and the per-pixel RMSE
left after both references' own noise is removed; a scene whose means differ
by more than 4 standard errors is reported as a MISMATCH, not as a result).
Then, under the CPU lock, `--repeats` interleaved equal-time runs of brume,
Cycles and Cycles with path guiding at `--threads` threads; each renderer's
sample count comes from a pilot to hit `--seconds` of render time.

Times: brume's is the one it reports for its render loop; Cycles' is the
wall time of `bpy.ops.render.render` for N samples minus that of a 1-sample
render of the same (persistent) scene, times N/(N − 1): the sync, BVH and
file write are left out of both. Efficiency = 1 / (MSE · seconds), the
reference's own noise subtracted (bench.py's `score`).

Where a scene's means do not match, a third renderer decides which one moved:

    python3 tools/cycles_bench.py third cloud --runs 20 --spp 96

renders the scene with Mitsuba 3 (llvm_ad_rgb, the scene's depth limit) in
independent runs and prints its mean ± SE beside the cached references'.

Needs bpy (python3 -m pip install bpy==5.0.1, Python 3.11): without it the
script says so and exits 2. Environment: BRUME_BENCH_CACHE, BRUME_CPU_LOCK
(default /tmp/cpu.lock here).
"""

import argparse
import contextlib
import hashlib
import json
import math
import os
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import bench  # noqa: E402
from exr_numpy import read_rgb  # noqa: E402

bench.LOCK = os.environ.get("BRUME_CPU_LOCK", "/tmp/cpu.lock")
CACHE = bench.CACHE
REPO = bench.REPO

# Scenes the Mitsuba table lacks, in its format (camera fov_x is horizontal).
CYCLES_EXTRA = {
    "CLOUD": {
        "file": "cycles_cloud",
        "title": "dense bright cloud (albedo 0.99, HG 0.8)",
        # The cumulus of scenes/cloud.toml, seen from below against a uniform sky;
        # the camera moved by the file's offset instead of translating the grid.
        "camera": {"position": [-1.04, 0.2, 7.98], "look_at": [-1.04, 2.05, 1.98], "fov_x": 44,
                   "resolution": [160, 120]},
        "lights": [
            {"type": "sun", "direction": bench.norm([-0.6, -0.6, 0.5]), "irradiance": [3.0] * 3},
            {"type": "environment", "radiance": [0.2, 0.3, 0.5]},
        ],
        "shapes": [],
        "medium": {"type": "vdb", "file": "volumes/cloud_translated.vdb", "scale": 40.0,
                   "albedo": [0.99] * 3, "g": 0.8},
        # Paths of hundreds of events matter at albedo 0.99 (0.99^63 = 0.53): a depth
        # limit both renderers count alike would still cut a visible part of the light.
        "max_depth": 1001,
    },
    "GROUND": {
        "file": "cycles_ground",
        "title": "diffuse ground and boxes under a uniform sky",
        "camera": {"position": [0, 2, 6], "look_at": [0, 0.4, 0], "fov_x": 50, "resolution": [160, 120]},
        "lights": [{"type": "environment", "radiance": [1.0, 1.0, 1.0]}],
        "shapes": [
            {"type": "ground", "center": [0, 0, 0], "half": 10.0, "albedo": [0.5] * 3},
            {"type": "box", "center": [-0.8, 0.5, 0], "half": [0.5, 0.5, 0.5], "albedo": [0.8, 0.3, 0.2]},
            {"type": "box", "center": [0.9, 0.3, 0.8], "half": [0.3, 0.3, 0.3], "albedo": [0.2, 0.5, 0.8]},
        ],
        "medium": None,
    },
}
# Variants of the bench smoke (B3) the tuning never saw, as checks on the held-out
# goal: a denser, brighter, more forward-scattering plume, and the plume lit from
# behind (the sun toward the camera, through the plume's forward lobe).
CYCLES_EXTRA["SMOKE_DENSE"] = dict(
    bench.SCENES["B3"], file="cycles_smoke_dense",
    title="the bench smoke 3× denser (albedo 0.95, HG 0.6)",
    medium=dict(bench.SCENES["B3"]["medium"], scale=60.0, albedo=[0.95] * 3, g=0.6))
CYCLES_EXTRA["SMOKE_BACKLIT"] = dict(
    bench.SCENES["B3"], file="cycles_smoke_backlit",
    title="the bench smoke lit from behind (HG 0.6)",
    lights=[{"type": "sun", "direction": bench.norm([0.3, -0.5, 0.8]), "irradiance": [4.0] * 3},
            {"type": "environment", "radiance": [0.15] * 3}],
    medium=dict(bench.SCENES["B3"]["medium"], g=0.6))
# The cloud lit from behind and above (the sun toward the camera), under a paler sky.
CYCLES_EXTRA["CLOUD_BACKLIT"] = dict(
    CYCLES_EXTRA["CLOUD"], file="cycles_cloud_backlit",
    title="the dense cloud lit from behind (albedo 0.99, HG 0.8)",
    lights=[{"type": "sun", "direction": bench.norm([0.4, -0.6, 0.7]), "irradiance": [3.0] * 3},
            {"type": "environment", "radiance": [0.3, 0.35, 0.45]}])
# The bench smoke and the dense cloud under a sky alone (no sun: light samples would
# ask the sky), as checks on held-out lighting.
CYCLES_EXTRA["SMOKE_SKY"] = dict(
    bench.SCENES["B3"], file="cycles_smoke_sky",
    title="the bench smoke under a uniform sky alone",
    lights=[{"type": "environment", "radiance": [0.8] * 3}])
CYCLES_EXTRA["CLOUD_SKY"] = dict(
    CYCLES_EXTRA["CLOUD"], file="cycles_cloud_sky",
    title="the dense cloud under a uniform sky alone (albedo 0.99, HG 0.8)",
    lights=[{"type": "environment", "radiance": [0.6, 0.7, 0.9]}])
CYCLES_EXTRA["CLOUD_MAP"] = dict(
    CYCLES_EXTRA["CLOUD"], file="cycles_cloud_map",
    title="the dense cloud under the HDR sky map alone (albedo 0.99, HG 0.8)",
    lights=[{"type": "environment_map", "file": "scenes/sky.exr"}])
# The bench smoke over its ground under the same map alone.
CYCLES_EXTRA["SMOKE_MAP"] = dict(
    bench.SCENES["B3"], file="cycles_smoke_map",
    title="the bench smoke under the HDR sky map alone",
    lights=[{"type": "environment_map", "file": "scenes/sky.exr"}])
# The same ground under scenes/sky.exr (a procedural HDR sky with a bright aureole).
CYCLES_EXTRA["GROUND_MAP"] = dict(CYCLES_EXTRA["GROUND"], file="cycles_ground_map",
                                  title="the ground and boxes under an HDR sky map",
                                  lights=[{"type": "environment_map", "file": "scenes/sky.exr"}])

# name → (table key, resolution): the scenes of the comparison.
HARNESS = {
    "smoke": ("B3", [160, 160]),
    "cloud": ("CLOUD", [160, 120]),
    "smoke_dense": ("SMOKE_DENSE", [160, 160]),
    "smoke_backlit": ("SMOKE_BACKLIT", [160, 160]),
    "cloud_backlit": ("CLOUD_BACKLIT", [160, 120]),
    "fog": ("B1", [128, 128]),
    "ground": ("GROUND", [160, 120]),
    "ground_map": ("GROUND_MAP", [160, 120]),
    "smoke_sky": ("SMOKE_SKY", [160, 160]),
    "cloud_sky": ("CLOUD_SKY", [160, 120]),
    "cloud_map": ("CLOUD_MAP", [160, 120]),
    "smoke_map": ("SMOKE_MAP", [160, 160]),
}
bench.SCENES.update(CYCLES_EXTRA)

# Each Cycles column: (path guiding, adaptive sampling). brume's own default
# may spread its samples (the automatic choice of `integrator.adaptive`), so
# Cycles gets its adaptive sampling too (its default threshold and minimum).
SETTINGS = {"cycles": (False, False), "cycles+guiding": (True, False),
            "cycles+adaptive": (False, True)}


def have_bpy():
    r = subprocess.run([sys.executable, "-c", "import bpy; print(bpy.app.version_string)"],
                       capture_output=True, text=True)
    return r.stdout.strip() if r.returncode == 0 else None


def vdb_path(key):
    m = bench.SCENES[key].get("medium")
    if not m or m["type"] != "vdb":
        return None
    return bench.CLOUD if m["file"].startswith("$") else str(REPO / m["file"])


# ------------------------------------------------------------------ Cycles worker


def cycles_worker(args):
    """Runs in its own process: build, warm up, time a 1-sample render, then the N-sample one."""
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    import cycles_scene

    spec = json.loads(Path(args.spec).read_text())
    out = Path(args.out)
    recorded = cycles_scene.build(spec, args.resolution, args.threads, args.guiding, args.seed,
                                  args.vdb, args.adaptive)
    scene = cycles_scene.bpy.context.scene
    cycles_scene.render(scene, 1, out.with_suffix(".warm.exr"))
    overhead = min(cycles_scene.render(scene, 1, out.with_suffix(".one.exr")) for _ in range(2))
    spp = args.spp
    if spp <= 0:
        # Pilots of growing size until one takes 0.3 s of render loop.
        n = 4
        while True:
            dt = cycles_scene.render(scene, n, out.with_suffix(".pilot.exr")) - overhead
            if dt >= 0.3 or n >= 1 << 16:
                break
            n *= 4
        spp = max(2, int(n / max(dt, 1e-6) * args.seconds))
    wall = cycles_scene.render(scene, spp, out)
    seconds = max(wall - overhead, 1e-6) * spp / (spp - 1) if spp > 1 else wall
    print(json.dumps({"seconds": seconds, "spp": spp, "wall": wall, "overhead": overhead,
                      "settings": recorded}))


def run_cycles(key, resolution, spp, threads, seed, mode, work, seconds=0.0, desc=None):
    """Cycles renders scene `key` (or `desc`, a changed copy of its table entry) in a worker process."""
    guiding, adaptive = mode
    spec = work / f"{key}-cycles.json"
    desc = json.loads(json.dumps(bench.SCENES[key] if desc is None else desc))
    for light in desc["lights"]:
        if "file" in light:
            light["path"] = str(REPO / light["file"])
    spec.write_text(json.dumps(desc))
    out = work / f"{key}-cycles-{int(guiding)}{int(adaptive)}-{seed}.exr"
    cmd = [sys.executable, __file__, "cycles-worker", "--spec", str(spec), "--out", str(out),
           "--spp", str(spp), "--seconds", str(seconds), "--threads", str(threads),
           "--seed", str(seed), "--resolution", f"{resolution[0]},{resolution[1]}"]
    if guiding:
        cmd.append("--guiding")
    if adaptive:
        cmd.append("--adaptive")
    if vdb_path(key):
        cmd += ["--vdb", vdb_path(key)]
    stdout, _, _, rss = bench.peak_rss_of(cmd)
    r = json.loads(stdout.strip().splitlines()[-1])
    return {"image": read_rgb(out), "seconds": r["seconds"], "spp": r["spp"], "rss": rss,
            "settings": r["settings"]}


# ------------------------------------------------------------------ references


def cached(name, tag, make):
    """Two halves (a, b) from the cache, or made by `make(seed)` and stored."""
    import numpy as np
    h = hashlib.sha256(json.dumps(tag, sort_keys=True).encode()).hexdigest()[:16]
    path = CACHE / "references" / f"{name}-{h}.npz"
    if path.exists():
        z = np.load(path)
        return z["a"], z["b"]
    path.parent.mkdir(parents=True, exist_ok=True)
    halves = [make(seed) for seed in (1_000_001, 2_000_003)]
    np.savez(path, a=halves[0], b=halves[1])
    return halves[0], halves[1]


def references(name, args, work, lock):
    """brume's converged reference and Cycles' long render, each as two halves (`lock` around each)."""
    key, res = HARNESS[name]
    tag = [bench.SCENES[key], res, args.ref_seconds, bench.MAX_DEPTH_MITSUBA]

    def brume_half(seed):
        with lock():
            spp = bench.brume_spp_for(key, res, args.threads, args.ref_seconds / 2, work)
            r = bench.run_brume(key, res, spp, args.threads, seed, work, "ref")
        print(f"  {name} reference half: brume {r['spp']} spp in {r['seconds']:.1f} s", flush=True)
        return r["image"]

    def cycles_half(seed):
        with lock():
            r = run_cycles(key, res, 0, args.threads, seed, SETTINGS["cycles"], work,
                           seconds=args.ref_seconds / 2)
        print(f"  {name} check half: cycles {r['spp']} spp in {r['seconds']:.1f} s", flush=True)
        return r["image"]

    # The binary's digest keys brume's reference: a changed renderer renders it anew.
    brume_digest = hashlib.sha256(bench.BRUME.read_bytes()).hexdigest()[:16]
    brume_ref = cached(f"{name}-brume", tag + ["brume", brume_digest], brume_half)
    cycles_ref = cached(f"{name}-cycles", tag + ["cycles", args.bpy], cycles_half)
    return brume_ref, cycles_ref


def match_check(brume_ref, cycles_ref):
    """Mean ratio Cycles / brume with its standard error, and the RMSE beyond both noises."""
    import numpy as np
    (ba, bb), (ca, cb) = brume_ref, cycles_ref
    b, c = 0.5 * (ba + bb), 0.5 * (ca + cb)
    n = b.size
    var_b = float(np.mean((ba - bb) ** 2)) / 4
    var_c = float(np.mean((ca - cb) ** 2)) / 4
    mb, mc = float(b.mean()), float(c.mean())
    # The image mean's variance: per-pixel variances (independent pixels) over n².
    se_ratio = (mc / mb) * math.sqrt(var_b / n / mb ** 2 + var_c / n / mc ** 2)
    excess = float(np.mean((b - c) ** 2)) - var_b - var_c
    channels = [float(c[..., k].mean() / max(b[..., k].mean(), 1e-30)) for k in range(3)]
    return {"ratio": mc / mb, "se": se_ratio, "channels": channels,
            "rel_rmse": math.sqrt(max(excess, 0.0)) / mb,
            "ok": abs(mc / mb - 1) <= 4 * se_ratio}


# ------------------------------------------------------------------ measurement


def one_run(who, key, res, spp, args, seed, work):
    if who == "brume":
        return bench.run_brume(key, res, spp, args.threads, seed, work, f"run-{seed}")
    return run_cycles(key, res, spp, args.threads, seed, SETTINGS[who], work, seconds=args.seconds)


def equal_time_runs(name, key, res, args, work, brume_ref):
    """`--repeats` interleaved runs of every renderer at about `--seconds` each, scored."""
    renderers = ["brume"] + list(SETTINGS)
    runs = {r: [] for r in renderers}
    settings = None
    spp = {"brume": bench.brume_spp_for(key, res, args.threads, args.seconds, work)}
    for rep in range(args.repeats):
        for who in renderers:
            run = one_run(who, key, res, spp.get(who, 0), args, 100 + rep, work)
            if who != "brume":  # brume's stays what its pilots chose (a spread run reports its mean)
                spp[who] = run["spp"]
            settings = run.pop("settings", settings)
            run.update(bench.score(run, *brume_ref))
            del run["image"]
            runs[who].append(run)
            print(f"  {name} {who}: {run['spp']} spp, {run['seconds']:.2f} s, rmse {run['rmse']:.4g}, "
                  f"eff {run['efficiency']:.4g}, noise/sample {run['noise']:.3f}, "
                  f"mean/ref {run['mean_ratio']:.4f}", flush=True)
    return runs, settings


def measure(name, args, work):
    """Equal-time runs of every renderer, scored against brume's reference."""
    key, res = HARNESS[name]
    # One hold of the CPU lock per scene (references, pilots and runs): on a shared
    # machine each acquisition waits for other jobs, and a scene's runs stay together.
    with bench.cpu_lock():
        brume_ref, cycles_ref = references(name, args, work, contextlib.nullcontext)
        check = match_check(brume_ref, cycles_ref)
        print(f"  {name} match: cycles / brume mean {check['ratio']:.4f} ± {check['se']:.2g} "
              f"(R, G, B {', '.join(f'{x:.4f}' for x in check['channels'])}), "
              f"relative RMSE beyond noise {check['rel_rmse']:.4f}"
              + ("" if check["ok"] else "  MISMATCH"), flush=True)
        runs, settings = equal_time_runs(name, key, res, args, work, brume_ref)
    summary = {r: {k: bench.median([x[k] for x in v]) for k in ("seconds", "spp", "rmse", "efficiency",
                                                                 "noise", "mean_ratio", "samples_per_s")}
               for r, v in runs.items()}
    return {"name": name, "key": key, "resolution": res, "check": check, "runs": summary,
            "settings": settings}


def table(rows):
    L = ["| scene | res | match: Cycles / brume mean (± SE) | renderer | spp | seconds | RMSE | "
         "noise per sample | efficiency 1/(MSE·s) | brume / this |",
         "|" + " --- |" * 10]
    for row in rows:
        c = row["check"]
        b = row["runs"]["brume"]["efficiency"]
        first = True
        for who, r in row["runs"].items():
            head = ["", "", ""]
            if first:
                head = [f"{row['name']}: {bench.SCENES[row['key']]['title']}",
                        f"{row['resolution'][0]}×{row['resolution'][1]}",
                        f"{c['ratio']:.4f} ± {c['se']:.2g}" + ("" if c["ok"] else " **MISMATCH**")]
            first = False
            L.append("| " + " | ".join(head + [
                who, str(int(r["spp"])), f"{r['seconds']:.2f}", f"{r['rmse']:.4g}", f"{r['noise']:.3f}",
                f"{r['efficiency']:.4g}", "1" if who == "brume" else f"**{b / r['efficiency']:.2f}×**"]) + " |")
    return "\n".join(L)


def update_markdown(path, result):
    """Replaces the generated Cycles section of BENCHMARKS.md (between its markers)."""
    import re
    m, a = result["machine"], result["args"]
    s = result["settings"] or {}
    lines = [
        "<!-- cycles:begin (generated by tools/cycles_bench.py; do not edit by hand) -->",
        f"Measured {m['date']} at commit `{m['commit']}` on {m['cpu']} ({m['cores']} cores), "
        f"{m['rustc']}, Python {m['python']}, Blender {a['bpy']} (bpy, Cycles on the CPU).",
        "",
        f"Command: `{a['command_line']}` — {a['threads']} threads, about {a['seconds']} s of render per run, "
        f"{a['repeats']} interleaved runs per renderer (medians); reference: brume, {a['ref_seconds']} s "
        f"in two seeded halves (its noise subtracted); match check: Cycles, {a['ref_seconds']} s.",
        "",
        result["table"],
        "",
        "Cycles settings (every column): " + ", ".join(f"`{k}={v}`" for k, v in sorted(s.items())
                                                       if k not in ("samples", "seed", "use_guiding",
                                                                    "use_surface_guiding",
                                                                    "use_volume_guiding",
                                                                    "use_adaptive_sampling")) +
        "; `cycles+guiding` sets `use_guiding`, `use_surface_guiding`, `use_volume_guiding`; "
        "`cycles+adaptive` sets `use_adaptive_sampling` (Cycles' default threshold 0.01 and "
        "automatic minimum), the others leave it off; "
        "view transform Standard, box filter of width 1, EXR 32-bit output.",
        "<!-- cycles:end -->",
    ]
    block = "\n".join(lines)
    text = path.read_text()
    pat = re.compile(r"<!-- cycles:begin.*?<!-- cycles:end -->", re.S)
    text = pat.sub(lambda _: block, text) if pat.search(text) else text + "\n" + block + "\n"
    path.write_text(text)
    print(f"updated {path}")


def cmd_run(args):
    args.bpy = have_bpy()
    if not args.bpy:
        print("cycles_bench.py: bpy is not importable: install Blender's Cycles with "
              "`python3 -m pip install bpy==5.0.1` (Python 3.11); nothing measured", file=sys.stderr)
        sys.exit(2)
    names = [n.strip() for n in args.scenes.split(",")]
    unknown = [n for n in names if n not in HARNESS]
    if unknown:
        print(f"cycles_bench.py: unknown scene {unknown[0]!r} (known: {', '.join(HARNESS)})", file=sys.stderr)
        sys.exit(2)
    if not args.no_build:
        with bench.cpu_lock():
            subprocess.run(["cargo", "build", "--release", "--bin", "brume"], cwd=REPO, check=True)
    work = CACHE / "cycles-work"
    work.mkdir(parents=True, exist_ok=True)
    rows = []
    for name in names:
        print(f"{name}: {bench.SCENES[HARNESS[name][0]]['title']}", flush=True)
        rows.append(measure(name, args, work))
    result = {"machine": bench.machine_info(), "args": vars(args), "rows": rows, "table": table(rows),
              "settings": next((r["settings"] for r in rows if r["settings"]), None)}
    print(result["table"])
    (CACHE / "cycles_last_run.json").write_text(json.dumps(result, indent=1, default=str))
    if args.markdown:
        update_markdown(Path(args.markdown), result)
    if not all(r["check"]["ok"] for r in rows):
        print("cycles_bench.py: some scenes' means do not match (see MISMATCH)", file=sys.stderr)
        sys.exit(1)


def cmd_third(args):
    """Mitsuba 3 (llvm_ad_rgb) as a third renderer on a harness scene's image mean.

    Where Cycles and brume disagree in the mean (MISMATCH), Mitsuba decides which
    one moved: `--runs` independent renders of `--spp` samples (their means'
    spread gives the standard error), compared with the cached references of
    the last `run` (brume's keyed by its binary's digest, Cycles' long render)."""
    import numpy as np
    if not bench.have_llvm():
        print("cycles_bench.py: Mitsuba's llvm_ad_rgb is not available (pip install mitsuba; "
              "apt-get install libllvm19); nothing measured", file=sys.stderr)
        sys.exit(2)
    key, res = HARNESS[args.scene]
    bench.MAX_DEPTH_MITSUBA = bench.SCENES[key].get("max_depth", bench.MAX_DEPTH_MITSUBA)
    work = CACHE / "cycles-work"
    work.mkdir(parents=True, exist_ok=True)
    means = []
    for i in range(args.runs):
        with bench.cpu_lock():
            r = bench.run_mitsuba("llvm_ad_rgb", key, res, args.spp, args.threads,
                                  args.first_seed + i, work)
        means.append(float(np.mean(r["image"][..., :3])))
        print(f"  mitsuba run {i + 1}/{args.runs}: {r['spp']} spp, mean {means[-1]:.6f}", flush=True)
    m = float(np.mean(means))
    se = float(np.std(means, ddof=1) / math.sqrt(len(means))) if len(means) > 1 else float("nan")
    print(f"{args.scene}: Mitsuba llvm mean {m:.6f} ± {se:.6f} ({args.runs} × {args.spp} spp)")
    for who in ("brume", "cycles"):
        found = sorted((CACHE / "references").glob(f"{args.scene}-{who}-*.npz"),
                       key=lambda f: f.stat().st_mtime)
        if not found:
            print(f"  {who}: no cached reference (run `cycles_bench.py run --scenes {args.scene}` first)")
            continue
        z = np.load(found[-1])
        v = float(np.mean(0.5 * (z["a"] + z["b"])))
        print(f"  {who} / Mitsuba = {v / m:.5f} ± {v * se / m ** 2:.5f} ({found[-1].name})")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = p.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("run", help="measure and print (and optionally write) the table")
    r.add_argument("--scenes", default=",".join(HARNESS))
    r.add_argument("--threads", type=int, default=2)
    r.add_argument("--seconds", type=float, default=4.0, help="target render seconds per run")
    r.add_argument("--repeats", type=int, default=3)
    r.add_argument("--ref-seconds", type=float, default=60.0)
    r.add_argument("--markdown", help="update the generated Cycles section of this file (BENCHMARKS.md)")
    r.add_argument("--no-build", action="store_true")
    t = sub.add_parser("third", help="Mitsuba llvm's image mean of a harness scene beside the cached references")
    t.add_argument("scene", choices=sorted(HARNESS))
    t.add_argument("--spp", type=int, default=96)
    t.add_argument("--runs", type=int, default=20)
    t.add_argument("--threads", type=int, default=2)
    t.add_argument("--first-seed", type=int, default=500, help="run i uses seed FIRST_SEED + i")
    w = sub.add_parser("cycles-worker", help=argparse.SUPPRESS)
    for name, t in [("--spec", str), ("--out", str), ("--spp", int), ("--seconds", float),
                    ("--threads", int), ("--seed", int), ("--vdb", str)]:
        w.add_argument(name, type=t)
    w.add_argument("--resolution", type=lambda s: [int(x) for x in s.split(",")])
    w.add_argument("--guiding", action="store_true")
    w.add_argument("--adaptive", action="store_true")
    args = p.parse_args()
    if args.cmd == "run":
        args.command_line = "python3 tools/cycles_bench.py " + " ".join(sys.argv[1:])
        cmd_run(args)
    elif args.cmd == "third":
        cmd_third(args)
    else:
        cycles_worker(args)


if __name__ == "__main__":
    main()
