#!/usr/bin/env python3
"""brume's benchmark harness: the bench scenes beside Mitsuba 3.

One parameter table (SCENES) defines B1-B5. From it this script writes
brume's scene files (scenes/bench/*.toml) and Mitsuba's scene dictionaries,
so both renderers see the same scene. For each scene and thread count it
renders, interleaved and under the shared CPU lock, brume and (when
`import mitsuba` works) Mitsuba's llvm_ad_rgb and scalar_rgb variants, and
compares each image with a converged reference rendered once and cached
outside the repository.

    python3 tools/bench.py scenes              # regenerate scenes/bench/*.toml
    python3 tools/bench.py run --markdown BENCHMARKS.md   # the whole table

Metrics, per renderer and run: samples/s (pixels × spp / render seconds,
scene loading and, for Mitsuba, kernel compilation excluded), RMSE over
all pixels and channels against the reference (the reference's own noise,
estimated from its two independently seeded halves, subtracted), efficiency
1 / (RMSE² · seconds), relative per-sample noise RMSE·√spp / mean(reference),
mean ratio to the reference (a bias check), peak resident memory of the
process, and for brume the null-collision fraction its tracking reports.

Environment: BRUME_BENCH_CACHE (default ~/.cache/brume-bench),
BRUME_BENCH_CLOUD (path to the third-party wdas_cloud_sixteenth.vdb for
B5; B5 is skipped without it), BRUME_CPU_LOCK (default /tmp/brume-cpu.lock).
"""

import argparse
import fcntl
import hashlib
import json
import math
import os
import platform
import re
import struct
import subprocess
import sys
import time
from contextlib import contextmanager
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
CACHE = Path(os.environ.get("BRUME_BENCH_CACHE", "~/.cache/brume-bench")).expanduser()
LOCK = os.environ.get("BRUME_CPU_LOCK", "/tmp/brume-cpu.lock")
CLOUD = os.environ.get("BRUME_BENCH_CLOUD")
BRUME = REPO / "target" / "release" / "brume"
DENSE = REPO / "target" / "release" / "examples" / "bench_dense"

# Mitsuba counts the camera vertex: its max_depth 64 is 63 scattering events in brume.
MAX_DEPTH_MITSUBA = 64
RR_DEPTH = 5


def norm(v):
    n = math.sqrt(sum(x * x for x in v))
    return [x / n for x in v]


def b4_cubes():
    """Cubes on the ground at (x, -d), half-size 0.05 d, coloured."""
    spots = [(-0.9, 5), (0.6, 10), (5.8, 20), (-11.6, 40), (-4.2, 70), (18, 100)]
    colours = [
        (0.8, 0.2, 0.2), (0.2, 0.7, 0.2), (0.2, 0.3, 0.8),
        (0.8, 0.7, 0.2), (0.7, 0.2, 0.7), (0.8, 0.8, 0.8),
    ]
    cubes = []
    for (x, d), c in zip(spots, colours):
        s = 0.05 * d
        cubes.append({"type": "box", "center": [x, s, -d], "half": [s, s, s], "albedo": list(c)})
    return cubes


SCENES = {
    "B1": {
        "file": "b1_homogeneous_cube",
        "title": "B1 homogeneous cube",
        "camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "fov_x": 40, "resolution": [256, 256]},
        "lights": [{"type": "environment", "radiance": [1, 1, 1]}],
        "shapes": [],
        "medium": {"type": "homogeneous", "min": [-0.5, -0.5, -0.5], "max": [0.5, 0.5, 0.5],
                   "sigma_t": 2.0, "albedo": [0.8] * 3, "g": 0.0},
    },
    "B2": {
        "file": "b2_hg_slab_sphere_light",
        "title": "B2 HG slab + sphere light",
        "camera": {"position": [0, 2.5, 8], "look_at": [0, 0.6, 0], "fov_x": 40, "resolution": [256, 256]},
        "lights": [],
        "shapes": [
            {"type": "ground", "center": [0, 0, 0], "half": 5.0, "albedo": [0.5] * 3},
            {"type": "sphere_light", "center": [0.5, 4, 0], "radius": 0.2, "radiance": [500] * 3},
        ],
        "medium": {"type": "homogeneous", "min": [-2, 0.75, -1], "max": [2, 1.25, 1],
                   "sigma_t": 2.0, "albedo": [0.95] * 3, "g": 0.7},
    },
    "B3": {
        "file": "b3_vdb_smoke",
        "title": "B3 VDB smoke",
        "camera": {"position": [0, 1.5, 4], "look_at": [0, 1, 0], "fov_x": 40, "resolution": [512, 512]},
        "lights": [
            {"type": "sun", "direction": norm([-1, -1.5, -0.5]), "irradiance": [4] * 3},
            {"type": "environment", "radiance": [0.1] * 3},
        ],
        "shapes": [{"type": "ground", "center": [0, 0, 0], "half": 8.0, "albedo": [0.5] * 3}],
        "medium": {"type": "vdb", "file": "volumes/bench/smoke_96.vdb", "scale": 20.0,
                   "albedo": [0.9] * 3, "g": 0.3},
    },
    "B4": {
        "file": "b4_airlight_fog",
        "title": "B4 airlight fog layer",
        "camera": {"position": [0, 1, 0], "look_at": [0, 1, -10], "fov_x": 40, "resolution": [384, 256]},
        "lights": [
            {"type": "sun", "direction": norm([0.4, -0.7, -0.6]), "irradiance": [2.6, 2.5, 2.3]},
            {"type": "environment", "radiance": [0.35, 0.5, 0.8]},
        ],
        "shapes": [{"type": "ground", "center": [0, 0, 0], "half": 150.0, "albedo": [0.4] * 3}]
        + b4_cubes(),
        "medium": {"type": "homogeneous", "min": [-150, -1, -150], "max": [150, 25, 150],
                   "sigma_t": 0.03, "albedo": [1.0] * 3, "g": 0.0, "camera_inside": True},
    },
    "B5": {
        "file": "b5_cloud",
        "title": "B5 Disney cloud 1/16",
        "camera": {"position": [-12, 72, 850], "look_at": [-12, 72, -45], "fov_x": 40, "resolution": [512, 512]},
        "lights": [
            {"type": "sun", "direction": norm([-0.5, -math.sqrt(0.5), -0.5]), "irradiance": [3] * 3},
            {"type": "environment", "radiance": [0.2] * 3},
        ],
        "shapes": [],
        # σt = density × 4 / voxel size, voxel size 10/3: 1.2 per unit density.
        "medium": {"type": "vdb", "file": "$BRUME_BENCH_CLOUD", "scale": 1.2,
                   "albedo": [0.99] * 3, "g": 0.85},
    },
}


# ---------------------------------------------------------------- brume scenes


def fov_y(cam):
    """brume's fov spans the image height; the table gives the full horizontal angle."""
    w, h = cam["resolution"]
    return math.degrees(2 * math.atan(math.tan(math.radians(cam["fov_x"]) / 2) * h / w))


def vec(v):
    return "[" + ", ".join(f"{float(x):.9g}" for x in v) + "]"


def brume_toml(key, resolution=None, spp=64, vdb_path=None):
    """brume's scene text for SCENES[key]; `vdb_path` overrides the grid file (absolute)."""
    s = SCENES[key]
    cam = dict(s["camera"])
    if resolution:
        cam["resolution"] = resolution
    out = [f"# {s['title']}: generated by tools/bench.py from its SCENES table; edit there.", ""]
    out += ["[camera]", f"position = {vec(cam['position'])}", f"look_at = {vec(cam['look_at'])}",
            f"fov = {fov_y(cam):.9g}   # {cam['fov_x']} degrees horizontally",
            f"resolution = [{cam['resolution'][0]}, {cam['resolution'][1]}]", ""]
    out += ["[integrator]", f"spp = {spp}", f"max_depth = {s.get('max_depth', MAX_DEPTH_MITSUBA) - 1}",
            f"rr_depth = {RR_DEPTH}", ""]
    for light in s["lights"]:
        out.append("[[light]]")
        if light["type"] == "environment":
            out += ['type = "environment"', f"radiance = {vec(light['radiance'])}"]
        elif light["type"] == "environment_map":  # tools/cycles_bench.py's image sky
            out += ['type = "environment_map"', f'file = "{REPO / light["file"]}"']
        else:
            out += ['type = "sun"', f"direction = {vec(light['direction'])}",
                    f"irradiance = {vec(light['irradiance'])}", "angular_radius = 0.0"]
        out.append("")
    for shape in s["shapes"]:
        out.append("[[shape]]")
        if shape["type"] == "ground":
            h = 2 * shape["half"]
            out += ['type = "quad"', f"center = {vec(shape['center'])}", "normal = [0.0, 1.0, 0.0]",
                    f"size = {vec([h, h])}",
                    f'material = {{ type = "diffuse", albedo = {vec(shape["albedo"])} }}']
        elif shape["type"] == "box":
            out += ['type = "box"', f"center = {vec(shape['center'])}",
                    f"size = {vec([2 * x for x in shape['half']])}",
                    f'material = {{ type = "diffuse", albedo = {vec(shape["albedo"])} }}']
        else:
            out += ['type = "sphere"', f"center = {vec(shape['center'])}",
                    f"radius = {shape['radius']}", f"emission = {vec(shape['radiance'])}"]
        out.append("")
    m = s["medium"]
    if m is None:  # a scene of surfaces only (tools/cycles_bench.py's ground)
        return "\n".join(out) + "\n"
    phase = '{ type = "isotropic" }' if m["g"] == 0 else f'{{ type = "hg", g = {m["g"]} }}'
    out.append("[[medium]]")
    if m["type"] == "homogeneous":
        out += ['type = "homogeneous"', f"sigma_t = {vec([m['sigma_t']] * 3)}",
                f"albedo = {vec(m['albedo'])}", f"phase = {phase}",
                f'bounds = {{ type = "box", min = {vec(m["min"])}, max = {vec(m["max"])} }}']
    else:
        path = vdb_path or m["file"]
        if not vdb_path and not path.startswith("$"):
            path = os.path.relpath(REPO / path, REPO / "scenes" / "bench")
        if path.startswith("$"):
            out.append(f"# tools/bench.py replaces the file with {path} (third-party: not in the repository)")
            path = "wdas_cloud_sixteenth.vdb"
        out += ['type = "vdb"', f'file = "{path}"', 'grid = "density"',
                f"density_scale = {m['scale']}", f"albedo = {vec(m['albedo'])}", f"phase = {phase}"]
    return "\n".join(out) + "\n"


def write_scenes():
    d = REPO / "scenes" / "bench"
    d.mkdir(parents=True, exist_ok=True)
    for key, s in SCENES.items():
        (d / f"{s['file']}.toml").write_text(brume_toml(key))
        print(f"wrote {d / (s['file'] + '.toml')}")


# -------------------------------------------------------------- Mitsuba scenes


def dense_volume(vdb):
    """A Mitsuba .vol file of the VDB's density (cached), and the world box of its unit cube."""
    vdb = Path(vdb).resolve()
    key = hashlib.sha256(f"{vdb}:{vdb.stat().st_size}:{vdb.stat().st_mtime}".encode()).hexdigest()[:16]
    raw = CACHE / "volumes" / f"{vdb.stem}-{key}.f32"
    vol = raw.with_suffix(".vol")
    if not vol.exists():
        raw.parent.mkdir(parents=True, exist_ok=True)
        subprocess.run([str(DENSE), str(vdb), "density", str(raw)], check=True)
        meta = json.loads(Path(str(raw) + ".json").read_text())
        nx, ny, nz = meta["resolution"]
        lo, hi = meta["world_min"], meta["world_max"]
        header = b"VOL" + bytes([3]) + struct.pack("<iiiii", 1, nx, ny, nz, 1)
        header += struct.pack("<6f", *lo, *hi)
        vol.write_bytes(header + raw.read_bytes())
        Path(str(vol) + ".json").write_text(json.dumps(meta))
    meta = json.loads(Path(str(vol) + ".json").read_text())
    return vol, meta["world_min"], meta["world_max"]


def mitsuba_dict(key, resolution, spp):
    """Mitsuba's scene dictionary for SCENES[key] (plain data; the worker builds transforms)."""
    s = SCENES[key]
    cam = s["camera"]
    w, h = resolution
    m = s["medium"]
    rgb = lambda v: {"type": "rgb", "value": list(v)}
    phase = {"type": "isotropic"} if m["g"] == 0 else {"type": "hg", "g": m["g"]}
    scene = {"type": "scene", "integrator": {"type": "volpath", "max_depth": MAX_DEPTH_MITSUBA,
                                             "rr_depth": RR_DEPTH}}
    if m["type"] == "homogeneous":
        scene["fog"] = {"type": "homogeneous", "sigma_t": m["sigma_t"], "albedo": rgb(m["albedo"]),
                        "phase": phase}
        lo, hi = m["min"], m["max"]
    else:
        vdb = CLOUD if m["file"].startswith("$") else str(REPO / m["file"])
        vol, lo, hi = dense_volume(vdb)
        scene["fog"] = {"type": "heterogeneous", "albedo": rgb(m["albedo"]), "phase": phase,
                        "scale": m["scale"],
                        "sigma_t": {"type": "gridvolume", "filename": str(vol),
                                    "to_world": ["box", lo, hi]}}
    fog = {"type": "ref", "id": "fog"}
    scene["medium_box"] = {"type": "cube", "to_world": ["box", lo, hi], "bsdf": {"type": "null"},
                           "interior": fog}
    sensor = {"type": "perspective", "fov": cam["fov_x"], "fov_axis": "x",
              "to_world": ["look_at", cam["position"], cam["look_at"], [0, 1, 0]],
              "film": {"type": "hdrfilm", "width": w, "height": h, "rfilter": {"type": "box"},
                       "pixel_format": "rgb", "component_format": "float32"},
              "sampler": {"type": "independent", "sample_count": spp}}
    inside = m.get("camera_inside", False)
    if inside:
        sensor["medium"] = fog
    scene["sensor"] = sensor
    for i, light in enumerate(s["lights"]):
        if light["type"] == "environment":
            scene[f"light{i}"] = {"type": "constant", "radiance": rgb(light["radiance"])}
        else:
            scene[f"light{i}"] = {"type": "directional", "direction": light["direction"],
                                  "irradiance": rgb(light["irradiance"])}
    for i, shape in enumerate(s["shapes"]):
        if shape["type"] == "sphere_light":
            d = {"type": "sphere", "center": shape["center"], "radius": shape["radius"],
                 "emitter": {"type": "area", "radiance": rgb(shape["radiance"])}}
        elif shape["type"] == "ground":
            c, r = shape["center"], shape["half"]
            d = {"type": "rectangle", "to_world": ["ground", c, r],
                 "bsdf": {"type": "diffuse", "reflectance": rgb(shape["albedo"])}}
        else:
            c, hs = shape["center"], shape["half"]
            lo_b = [c[k] - hs[k] for k in range(3)]
            hi_b = [c[k] + hs[k] for k in range(3)]
            d = {"type": "cube", "to_world": ["box", lo_b, hi_b],
                 "bsdf": {"type": "diffuse", "reflectance": rgb(shape["albedo"])}}
        if inside:
            # Surfaces inside the fog: rays leaving them are still in it.
            d["exterior"] = fog
            if shape["type"] == "ground":
                d["interior"] = fog
        scene[f"shape{i}"] = d
    return scene


def build_transforms(d, mi):
    """Turns the worker-independent transform lists into mi.ScalarTransform4f."""
    T = mi.ScalarTransform4f
    if isinstance(d, dict):
        return {k: build_transforms(v, mi) for k, v in d.items()}
    if isinstance(d, list) and d and isinstance(d[0], str):
        kind = d[0]
        if kind == "box":
            lo, hi = d[1], d[2]
            c = [(a + b) / 2 for a, b in zip(lo, hi)]
            h = [(b - a) / 2 for a, b in zip(lo, hi)]
            return T().translate(c).scale(h)  # Mitsuba's cube is [-1, 1]³
        if kind == "look_at":
            return T().look_at(origin=d[1], target=d[2], up=d[3])
        if kind == "ground":
            return T().translate(d[1]).rotate([1, 0, 0], -90).scale([d[2], d[2], 1])
    return d


def unit_box(lo, hi, mi):
    """Maps [0,1]³ (a grid volume's space) onto the box [lo, hi]."""
    return mi.ScalarTransform4f().translate(lo).scale([b - a for a, b in zip(lo, hi)])


def mitsuba_worker(args):
    """Runs in its own process: one variant, a warm-up render, then timed renders."""
    import drjit as dr
    import mitsuba as mi
    import numpy as np

    mi.set_variant(args.variant)
    dr.set_thread_count(args.threads)
    spec = json.loads(Path(args.spec).read_text())
    vol = spec.get("fog", {}).get("sigma_t")
    if isinstance(vol, dict):
        lo, hi = vol["to_world"][1], vol["to_world"][2]
        vol["to_world"] = unit_box(lo, hi, mi)
    scene = mi.load_dict(build_transforms(spec, mi))
    t0 = time.perf_counter()
    img = mi.render(scene, spp=args.warmup_spp, seed=10_000 + args.seed)
    np.array(img)
    warm = time.perf_counter() - t0
    spp = args.spp
    if spp <= 0:
        # Pick spp for about `seconds` of rendering from compiled pilots of at least 0.3 s.
        n = args.warmup_spp
        while True:
            t0 = time.perf_counter()
            np.array(mi.render(scene, spp=n, seed=20_000 + args.seed))
            dt = time.perf_counter() - t0
            if dt >= 0.3 or n >= 1 << 16:
                break
            n *= 4
        spp = max(1, int(n / dt * args.seconds))
    total = None
    elapsed = 0.0
    done = 0
    chunk = max(1, min(spp, args.max_chunk))
    seed = args.seed
    while done < spp:
        n = min(chunk, spp - done)
        t0 = time.perf_counter()
        a = np.array(mi.render(scene, spp=n, seed=seed))
        elapsed += time.perf_counter() - t0
        total = a * n if total is None else total + a * n
        done += n
        seed += 7919
    img = (total / done).astype(np.float32)
    np.save(args.out, img)
    print(json.dumps({"seconds": elapsed, "spp": done, "warmup_seconds": warm}))


# ---------------------------------------------------------------- measurement


@contextmanager
def cpu_lock():
    with open(LOCK, "a") as f:
        fcntl.flock(f, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(f, fcntl.LOCK_UN)


def peak_rss_of(cmd):
    """Runs `cmd` with its own rusage: (stdout, stderr, wall seconds, peak RSS in bytes)."""
    t0 = time.perf_counter()
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    # communicate() reaps the child, losing its rusage: read the pipes first, then wait4.
    out = p.stdout.read()
    err = p.stderr.read()
    _, status, usage = os.wait4(p.pid, 0)
    p.returncode = os.waitstatus_to_exitcode(status)
    wall = time.perf_counter() - t0
    if p.returncode != 0:
        raise RuntimeError(f"{' '.join(map(str, cmd))} failed ({p.returncode}):\n{err[-2000:]}")
    return out, err, wall, usage.ru_maxrss * 1024


def read_exr(path):
    """The beauty of an EXR (brume's film files also hold sums and counts), without Mitsuba."""
    from exr_numpy import read_rgb
    return read_rgb(path)


def scene_file(key, resolution, spp, work):
    m = SCENES[key]["medium"]
    vdb = None
    if m and m["type"] == "vdb":
        vdb = CLOUD if m["file"].startswith("$") else str(REPO / m["file"])
    path = work / f"{key}-{resolution[0]}x{resolution[1]}.toml"
    path.write_text(brume_toml(key, resolution, spp, vdb_path=vdb))
    return path


RATE_RE = re.compile(r"at (\d+) spp in ([0-9.]+) s")
# A piloted render (brume's automatic choice or --adaptive on): "at N spp" is
# the most of any pixel; the samples taken are the pilot's and the mean's.
PILOTED_RE = re.compile(r"^adaptive: pilot (\d+) spp .* \(mean ([0-9.]+)\)", re.M)
TRACK_RE = re.compile(r"tracking: ([0-9.]+) tentative collisions per sample, null fraction ([0-9.]+)"
                      r"(?:, ([0-9.]+) exact voxel steps per sample)?")


def run_brume(key, resolution, spp, threads, seed, work, out_name):
    scene = scene_file(key, resolution, spp, work)
    exr = work / f"{out_name}.exr"
    cmd = [str(BRUME), "render", str(scene), "--threads", str(threads), "--seed", str(seed),
           "--out", str(exr), "--png", str(work / f"{out_name}.png")]
    _, err, wall, rss = peak_rss_of(cmd)
    m = RATE_RE.search(err)
    if not m:
        raise RuntimeError(f"no timing in brume's output:\n{err}")
    t = TRACK_RE.search(err)
    seconds = float(m.group(2))
    piloted = PILOTED_RE.search(err)
    spp = int(m.group(1))
    if piloted:
        spp = int(piloted.group(1)) + float(piloted.group(2))
    return {"image": read_exr(exr), "seconds": seconds, "spp": spp, "rss": rss,
            "load_seconds": wall - seconds,
            "collisions": float(t.group(1)) if t else None,
            "null_fraction": float(t.group(2)) if t else None,
            "voxel_steps": float(t.group(3)) if t and t.group(3) else 0.0}


def brume_spp_for(key, resolution, threads, seconds, work):
    """spp for about `seconds` of brume rendering, from pilots of at least 0.3 s."""
    n = 1
    while True:
        pilot = run_brume(key, resolution, n, threads, 7, work, "pilot")
        if pilot["seconds"] >= 0.3 or n >= 1 << 16:
            return max(1, int(n / pilot["seconds"] * seconds))
        n *= 4


def run_mitsuba(variant, key, resolution, spp, threads, seed, work, seconds=0.0):
    spec = work / f"{key}-mitsuba.json"
    spec.write_text(json.dumps(mitsuba_dict(key, resolution, max(spp, 1))))
    out = work / f"{key}-{variant}-{seed}.npy"
    warm = 1 if variant.startswith("scalar") else 4
    cmd = [sys.executable, __file__, "mitsuba-worker", "--variant", variant, "--spec", str(spec),
           "--spp", str(spp), "--seconds", str(seconds), "--threads", str(threads),
           "--seed", str(seed), "--out", str(out), "--warmup-spp", str(warm)]
    stdout, _, _, rss = peak_rss_of(cmd)
    import numpy as np
    r = json.loads(stdout.strip().splitlines()[-1])
    return {"image": np.load(out), "seconds": r["seconds"], "spp": r["spp"], "rss": rss,
            "load_seconds": None, "collisions": None, "null_fraction": None, "voxel_steps": None}


def have_mitsuba():
    try:
        import mitsuba  # noqa: F401
        return True
    except ImportError:
        return False


def have_llvm():
    r = subprocess.run([sys.executable, "-c", "import mitsuba as mi; mi.set_variant('llvm_ad_rgb')"],
                       capture_output=True)
    return r.returncode == 0


def reference(key, resolution, args, work):
    """The converged reference: two independently seeded halves (cached)."""
    import numpy as np
    who = args.reference
    tag = json.dumps([SCENES[key], resolution, args.ref_seconds, who, MAX_DEPTH_MITSUBA], sort_keys=True)
    h = hashlib.sha256(tag.encode()).hexdigest()[:16]
    path = CACHE / "references" / f"{key}-{resolution[0]}x{resolution[1]}-{who}-{h}.npz"
    if path.exists():
        z = np.load(path)
        return z["a"], z["b"], str(z["who"])
    path.parent.mkdir(parents=True, exist_ok=True)
    halves = []
    for seed in (1_000_001, 2_000_003):
        with cpu_lock():
            if who == "brume":
                # Rate from a pilot, then half the budget each.
                spp = brume_spp_for(key, resolution, args.ref_threads, args.ref_seconds / 2, work)
                r = run_brume(key, resolution, spp, args.ref_threads, seed, work, "ref")
            else:
                r = run_mitsuba("llvm_ad_rgb", key, resolution, 0, args.ref_threads, seed, work,
                                seconds=args.ref_seconds / 2)
        print(f"  reference {key} half: {who}, {r['spp']} spp in {r['seconds']:.1f} s", flush=True)
        halves.append(r["image"])
    np.savez(path, a=halves[0], b=halves[1], who=who)
    return halves[0], halves[1], who


def score(run, ref_a, ref_b):
    import numpy as np
    ref = 0.5 * (ref_a + ref_b)
    # E[(x - ref)²] = error² + var(ref); var(ref) = E[(a - b)²] / 4 for two equal halves.
    ref_var = float(np.mean((ref_a - ref_b) ** 2)) / 4
    mse = float(np.mean((run["image"] - ref) ** 2)) - ref_var
    mse = max(mse, 1e-30)
    rmse = math.sqrt(mse)
    mean_ref = float(np.mean(ref))
    pixels = run["image"].shape[0] * run["image"].shape[1]
    return {
        "rmse": rmse,
        "efficiency": 1.0 / (mse * run["seconds"]),
        "samples_per_s": pixels * run["spp"] / run["seconds"],
        "noise": rmse * math.sqrt(run["spp"]) / mean_ref,
        "mean_ratio": float(np.mean(run["image"])) / mean_ref,
        "ref_noise": math.sqrt(ref_var) / mean_ref,
    }


def median(xs):
    xs = sorted(xs)
    n = len(xs)
    return xs[n // 2] if n % 2 else 0.5 * (xs[n // 2 - 1] + xs[n // 2])


def measure_scene(key, args, renderers, work):
    s = SCENES[key]
    w, h = s["camera"]["resolution"]
    resolution = [max(8, int(w * args.scale)), max(8, int(h * args.scale))]
    rows = []
    ref_a = ref_b = None
    if key != "B5" or args.b5_reference:
        ref_a, ref_b, who = reference(key, resolution, args, work)
    for threads in args.threads:
        runs = {r: [] for r in renderers}
        with cpu_lock():
            spp_brume = brume_spp_for(key, resolution, threads, args.seconds, work)
            spp_mitsuba = {}
            for rep in range(args.repeats):
                seed = 100 + rep
                for r in renderers:
                    if r == "brume":
                        run = run_brume(key, resolution, spp_brume, threads, seed, work, f"run{rep}")
                    else:
                        secs = args.seconds * (args.scalar_fraction if r == "scalar_rgb" else 1.0)
                        run = run_mitsuba(r, key, resolution, spp_mitsuba.get(r, 0), threads, seed,
                                          work, seconds=secs)
                        spp_mitsuba[r] = run["spp"]
                    if ref_a is not None:
                        run.update(score(run, ref_a, ref_b))
                    else:
                        pixels = resolution[0] * resolution[1]
                        run["samples_per_s"] = pixels * run["spp"] / run["seconds"]
                    del run["image"]
                    runs[r].append(run)
                    print(f"  {key} t={threads} {r}: {run['spp']} spp, {run['seconds']:.2f} s, "
                          f"{run['samples_per_s'] / 1e6:.3f} M/s"
                          + (f", rmse {run['rmse']:.4g}, eff {run['efficiency']:.4g}" if "rmse" in run else ""),
                          flush=True)
        summary = {r: {k: median([x[k] for x in v]) for k in v[0] if v[0][k] is not None}
                   for r, v in runs.items()}
        rows.append({"scene": key, "title": s["title"], "threads": threads, "resolution": resolution,
                     "runs": summary})
    return rows


def fmt_rate(x):
    return f"{x / 1e6:.3f} M" if x >= 1e5 else f"{x / 1e3:.1f} k"


def markdown(rows, args, renderers, machine, vdb_stats):
    L = []
    L.append("| scene | threads | res | brume samples/s | llvm samples/s | scalar samples/s | "
             "noise brume / llvm | mean brume / llvm vs ref | eff. ratio vs llvm | eff. ratio vs scalar | "
             "brume null fraction | collisions/sample | peak RSS brume / llvm |")
    L.append("|" + " --- |" * 13)
    for row in rows:
        r = row["runs"]
        b = r.get("brume", {})
        l = r.get("llvm_ad_rgb", {})
        sc = r.get("scalar_rgb", {})
        get = lambda d, k, f: f(d[k]) if k in d else "—"
        ratio = lambda d: f"{b['efficiency'] / d['efficiency']:.2f}" if "efficiency" in d and "efficiency" in b else "—"
        L.append(" | ".join([
            f"| {row['title']}", str(row["threads"]), f"{row['resolution'][0]}×{row['resolution'][1]}",
            get(b, "samples_per_s", fmt_rate), get(l, "samples_per_s", fmt_rate),
            get(sc, "samples_per_s", fmt_rate),
            f"{get(b, 'noise', lambda x: f'{x:.3f}')} / {get(l, 'noise', lambda x: f'{x:.3f}')}",
            f"{get(b, 'mean_ratio', lambda x: f'{x:.4f}')} / {get(l, 'mean_ratio', lambda x: f'{x:.4f}')}",
            ratio(l), ratio(sc),
            get(b, "null_fraction", lambda x: f"{x:.3f}"), get(b, "collisions", lambda x: f"{x:.1f}") + (
                f" + {b['voxel_steps']:.1f} voxel steps" if b.get("voxel_steps") else ""),
            f"{get(b, 'rss', lambda x: f'{x / 2**20:.0f} MiB')} / {get(l, 'rss', lambda x: f'{x / 2**20:.0f} MiB')}",
        ]) + " |")
    return "\n".join(L)


def machine_info():
    cpu = "unknown"
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    mitsuba = "not installed"
    try:
        import mitsuba as mi
        mitsuba = mi.__version__
    except ImportError:
        pass
    rustc = subprocess.run(["rustc", "--version"], capture_output=True, text=True).stdout.strip()
    commit = subprocess.run(["git", "-C", str(REPO), "rev-parse", "--short", "HEAD"],
                            capture_output=True, text=True).stdout.strip()
    return {"cpu": cpu, "cores": os.cpu_count(), "os": platform.platform(), "python": platform.python_version(),
            "mitsuba": mitsuba, "rustc": rustc, "commit": commit,
            "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())}


def vdb_statistics():
    """Load time and bytes per active voxel of the grids, from `brume info`."""
    out = {}
    for key in ("B3", "B5"):
        f = SCENES[key]["medium"]["file"]
        path = CLOUD if f.startswith("$") else str(REPO / f)
        if not path or not Path(path).exists():
            continue
        t0 = time.perf_counter()
        text = subprocess.run([str(BRUME), "info", path], capture_output=True, text=True).stdout
        secs = time.perf_counter() - t0
        m = re.search(r"memory: (\d+) bytes \(([0-9.]+) bytes per active voxel\)", text)
        out[key] = {"info_seconds": secs, "bytes": int(m.group(1)) if m else None,
                    "bytes_per_voxel": float(m.group(2)) if m else None}
    return out


def cmd_run(args):
    if not args.no_build:
        with cpu_lock():
            subprocess.run(["cargo", "build", "--release", "--bin", "brume", "--example", "bench_dense"],
                           cwd=REPO, check=True)
    renderers = ["brume"]
    if have_mitsuba():
        if have_llvm():
            renderers.append("llvm_ad_rgb")
        else:
            print("Mitsuba's llvm_ad_rgb does not load (apt-get install libllvm19): skipped")
        if not args.no_scalar:
            renderers.append("scalar_rgb")
    else:
        print("mitsuba is not importable (pip install mitsuba): brume only")
        if args.reference != "brume":
            args.reference = "brume"
    if args.reference == "mitsuba" and "llvm_ad_rgb" not in renderers:
        args.reference = "brume"
    work = CACHE / "work"
    work.mkdir(parents=True, exist_ok=True)
    keys = [k.strip().upper() for k in args.scenes.split(",")]
    if "B5" in keys and not (CLOUD and Path(CLOUD).exists()):
        print("B5 needs BRUME_BENCH_CLOUD=/path/to/wdas_cloud_sixteenth.vdb: skipped")
        keys.remove("B5")
    rows = []
    for key in keys:
        print(f"{key}: {SCENES[key]['title']}", flush=True)
        rows += measure_scene(key, args, [r for r in renderers if key != "B5" or r != "scalar_rgb"], work)
    machine = machine_info()
    vdb = vdb_statistics()
    table = markdown(rows, args, renderers, machine, vdb)
    print(table)
    result = {"machine": machine, "args": vars(args), "rows": rows, "vdb": vdb, "table": table}
    (CACHE / "last_run.json").write_text(json.dumps(result, indent=1))
    if args.markdown:
        update_markdown(Path(args.markdown), result)


def update_markdown(path, result):
    """Replaces the generated section of BENCHMARKS.md (between the markers)."""
    m = result["machine"]
    a = result["args"]
    lines = [
        "<!-- bench:begin (generated by tools/bench.py; do not edit by hand) -->",
        f"Measured {m['date']} at commit `{m['commit']}` on {m['cpu']} ({m['cores']} cores), "
        f"{m['os']}, {m['rustc']}, Python {m['python']}, Mitsuba {m['mitsuba']}.",
        "",
        f"Command: `{a['command_line']}` — scale {a['scale']} of each scene's resolution, "
        f"about {a['seconds']} s per run, {a['repeats']} interleaved runs per renderer (medians), "
        f"reference: {a['reference']} with {a['ref_seconds']} s at {a['ref_threads']} threads.",
        "",
        result["table"],
        "",
    ]
    for key, v in result["vdb"].items():
        if v.get("bytes"):
            lines.append(f"- {key} grid: {v['bytes']} bytes in memory, {v['bytes_per_voxel']:.2f} bytes per "
                         f"active voxel; `brume info` (load + report) {v['info_seconds']:.2f} s.")
    for row in result["rows"]:
        b = row["runs"].get("brume", {})
        if row["scene"] == "B5" and "load_seconds" in b:
            lines.append(f"- B5 brume, {row['threads']} threads: load + write {b['load_seconds']:.2f} s "
                         f"beside {b['seconds']:.2f} s of rendering.")
    lines.append("<!-- bench:end -->")
    block = "\n".join(lines)
    text = path.read_text() if path.exists() else "# Benchmarks\n\n<!-- bench:begin -->\n<!-- bench:end -->\n"
    pat = re.compile(r"<!-- bench:begin.*?<!-- bench:end -->", re.S)
    text = pat.sub(lambda _: block, text) if pat.search(text) else text + "\n" + block + "\n"
    path.write_text(text)
    print(f"updated {path}")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = p.add_subparsers(dest="cmd", required=True)
    sub.add_parser("scenes", help="write scenes/bench/*.toml from the SCENES table")
    r = sub.add_parser("run", help="measure and print (and optionally write) the table")
    r.add_argument("--scenes", default="B1,B2,B3,B4,B5")
    r.add_argument("--threads", type=lambda s: [int(x) for x in s.split(",")], default=[1, 2])
    r.add_argument("--scale", type=float, default=0.5, help="fraction of each scene's resolution")
    r.add_argument("--seconds", type=float, default=4.0, help="target render seconds per run")
    r.add_argument("--repeats", type=int, default=2)
    r.add_argument("--scalar-fraction", type=float, default=1.0,
                   help="scalar_rgb runs get this fraction of --seconds")
    r.add_argument("--no-scalar", action="store_true")
    r.add_argument("--reference", choices=["mitsuba", "brume"], default="mitsuba")
    r.add_argument("--ref-seconds", type=float, default=120.0)
    r.add_argument("--ref-threads", type=int, default=2)
    r.add_argument("--b5-reference", action="store_true", help="also score B5 against a reference")
    r.add_argument("--markdown", help="update the generated section of this file (BENCHMARKS.md)")
    r.add_argument("--no-build", action="store_true")
    w = sub.add_parser("mitsuba-worker", help=argparse.SUPPRESS)
    for name, t in [("--variant", str), ("--spec", str), ("--spp", int), ("--seconds", float),
                    ("--threads", int), ("--seed", int), ("--out", str), ("--warmup-spp", int),
                    ("--max-chunk", int)]:
        w.add_argument(name, type=t, default=1 << 20 if name == "--max-chunk" else None)
    args = p.parse_args()
    if args.cmd == "scenes":
        write_scenes()
    elif args.cmd == "run":
        args.command_line = "python3 tools/bench.py " + " ".join(sys.argv[1:])
        cmd_run(args)
    else:
        mitsuba_worker(args)


if __name__ == "__main__":
    main()
