"""Builds a Blender Cycles scene (through bpy) from one entry of the bench
parameter table (tools/bench.py SCENES format) and times its renders.

Imported only by the worker process of tools/cycles_bench.py, after bpy
loaded. Unit matching, each checked by the harness's mean ratios:
- camera: horizontal sensor fit, `angle` = the table's horizontal field of
  view; box pixel filter of width 1 (brume averages samples over the pixel);
- environment: a Background node of strength 1 whose colour is the radiance;
- sun: Cycles' sun strength is irradiance in W/m² (the radiance a white
  Lambertian surface facing it reflects is strength/π), angle 0 (a delta
  direction, as brume's `angular_radius = 0`);
- media: Volume Scatter (σs = density·colour, Henyey-Greenstein g) plus
  Volume Absorption (σa = density·(1 − colour)) with colour = albedo and
  density = σt, so σt and the albedo are brume's; a VDB's density attribute
  is multiplied by the table's scale, its clipping set to 0 (Cycles would
  otherwise drop voxels below 0.001);
- Standard view transform, no denoising, adaptive sampling only when asked
  (the harness's `cycles+adaptive` column), no clamping,
  no glossy filter, no light threshold, unbiased volumes.
"""

import math
import time

import bpy
from mathutils import Matrix, Vector



def reset():
    """An empty scene rendered by Cycles on the CPU."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    return scene


def settings(scene, resolution, threads, guiding, seed, bounces, adaptive=False):
    """Render settings that make Cycles estimate what brume does; returns them for the report."""
    c = scene.cycles
    values = {
        "samples": 1, "use_adaptive_sampling": adaptive, "use_denoising": False,
        "pixel_filter_type": "BOX", "filter_width": 1.0, "max_bounces": bounces,
        "diffuse_bounces": bounces, "glossy_bounces": bounces, "transmission_bounces": bounces,
        "volume_bounces": bounces, "transparent_max_bounces": min(4 * bounces, 1024),
        "sample_clamp_direct": 0.0, "sample_clamp_indirect": 0.0, "blur_glossy": 0.0,
        "caustics_reflective": True, "caustics_refractive": True, "light_sampling_threshold": 0.0,
        "volume_biased": False, "use_light_tree": True, "seed": seed, "use_animated_seed": False,
        "use_guiding": guiding, "use_surface_guiding": guiding, "use_volume_guiding": guiding,
        "use_deterministic_guiding": True,
    }
    for k, v in values.items():
        setattr(c, k, v)
    r = scene.render
    r.resolution_x, r.resolution_y = resolution
    r.resolution_percentage = 100
    r.threads_mode = "FIXED"
    r.threads = threads
    r.use_persistent_data = True
    r.film_transparent = False
    r.image_settings.file_format = "OPEN_EXR"
    r.image_settings.color_depth = "32"
    r.image_settings.exr_codec = "ZIP"
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    recorded = dict(values)
    recorded.update({k: getattr(c, k) for k in ("direct_light_sampling_type", "sampling_pattern",
                                                 "guiding_training_samples", "min_light_bounces")})
    return recorded


def look_at(obj, position, target):
    """Places `obj` at `position` looking along −Z toward `target`, +Y up (the table's frame).

    Built from the basis itself: `to_track_quat` aligns the up axis with
    Blender's +Z, which would roll the camera in the table's Y-up frame.
    """
    f = (Vector(target) - Vector(position)).normalized()
    up = Vector((0.0, 1.0, 0.0)) if abs(f.y) < 0.999 else Vector((0.0, 0.0, -1.0))
    r = f.cross(up).normalized()
    u = r.cross(f)
    m = Matrix((r, u, -f)).transposed().to_4x4()
    m.translation = Vector(position)
    obj.matrix_world = m


def add_camera(scene, cam):
    data = bpy.data.cameras.new("camera")
    data.sensor_fit = "HORIZONTAL"
    data.angle = math.radians(cam["fov_x"])
    data.clip_start, data.clip_end = 1e-3, 1e5
    obj = bpy.data.objects.new("camera", data)
    scene.collection.objects.link(obj)
    look_at(obj, cam["position"], cam["look_at"])
    scene.camera = obj


def add_world(scene, radiance):
    world = bpy.data.worlds.new("world")
    world.use_nodes = True
    bg = world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (*radiance, 1.0)
    bg.inputs["Strength"].default_value = 1.0
    scene.world = world


def add_world_map(scene, path):
    """A lat-long map looked up as brume does (row 0 at +Y, u = φ/2π from +X toward +Z, nearest texel).

    Blender's equirectangular lookup of a direction D is u = 0.5 − atan2(D.y, D.x)/2π
    with +Z up; D = (−d.x, d.z, d.y) of brume's direction d gives the same texel.
    """
    world = bpy.data.worlds.new("world")
    world.use_nodes = True
    tree = world.node_tree
    bg = tree.nodes["Background"]
    coords = tree.nodes.new("ShaderNodeTexCoord")
    split = tree.nodes.new("ShaderNodeSeparateXYZ")
    neg = tree.nodes.new("ShaderNodeMath")
    neg.operation = "MULTIPLY"
    neg.inputs[1].default_value = -1.0
    join = tree.nodes.new("ShaderNodeCombineXYZ")
    tex = tree.nodes.new("ShaderNodeTexEnvironment")
    tex.image = bpy.data.images.load(path)
    tex.image.colorspace_settings.name = "Linear Rec.709"
    tex.interpolation = "Closest"
    tree.links.new(coords.outputs["Generated"], split.inputs[0])
    tree.links.new(split.outputs["X"], neg.inputs[0])
    tree.links.new(neg.outputs["Value"], join.inputs["X"])
    tree.links.new(split.outputs["Z"], join.inputs["Y"])
    tree.links.new(split.outputs["Y"], join.inputs["Z"])
    tree.links.new(join.outputs["Vector"], tex.inputs["Vector"])
    tree.links.new(tex.outputs["Color"], bg.inputs["Color"])
    bg.inputs["Strength"].default_value = 1.0
    scene.world = world


def add_sun(scene, light):
    """A delta sun: strength = the largest channel of the irradiance, colour the rest."""
    e = light["irradiance"]
    peak = max(e)
    data = bpy.data.lights.new("sun", type="SUN")
    data.energy = peak
    data.color = [x / peak for x in e]
    data.angle = 0.0
    obj = bpy.data.objects.new("sun", data)
    scene.collection.objects.link(obj)
    d = Vector(light["direction"])
    look_at(obj, [0.0, 0.0, 0.0], list(d))


def mesh_object(scene, name, verts, faces, material):
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(verts, [], faces)
    mesh.update()
    mesh.materials.append(material)
    obj = bpy.data.objects.new(name, mesh)
    scene.collection.objects.link(obj)
    return obj


def box_geometry(lo, hi):
    verts = [(x, y, z) for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])]
    # Vertex index = 4·ix + 2·iy + iz; faces wound outward.
    faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    return verts, faces


def diffuse(name, albedo):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes = mat.node_tree.nodes
    nodes.clear()
    bsdf = nodes.new("ShaderNodeBsdfDiffuse")
    bsdf.inputs["Color"].default_value = (*albedo, 1.0)
    bsdf.inputs["Roughness"].default_value = 0.0
    out = nodes.new("ShaderNodeOutputMaterial")
    mat.node_tree.links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
    return mat


def add_shape(scene, i, shape):
    if shape["type"] == "ground":
        c, h = shape["center"], shape["half"]
        verts = [(c[0] - h, c[1], c[2] - h), (c[0] - h, c[1], c[2] + h),
                 (c[0] + h, c[1], c[2] + h), (c[0] + h, c[1], c[2] - h)]
        mesh_object(scene, f"ground{i}", verts, [(0, 1, 2, 3)], diffuse(f"ground{i}", shape["albedo"]))
    elif shape["type"] == "box":
        c, hs = shape["center"], shape["half"]
        verts, faces = box_geometry([c[k] - hs[k] for k in range(3)], [c[k] + hs[k] for k in range(3)])
        mesh_object(scene, f"box{i}", verts, faces, diffuse(f"box{i}", shape["albedo"]))
    else:
        raise SystemExit(f"cycles_scene.py: shape type {shape['type']!r} has no Cycles translation")


def volume_material(medium, density_attribute):
    """σs = σt·albedo (Volume Scatter, HG g), σa = σt·(1 − albedo) (Volume Absorption)."""
    mat = bpy.data.materials.new("medium")
    mat.use_nodes = True
    tree = mat.node_tree
    tree.nodes.clear()
    scatter = tree.nodes.new("ShaderNodeVolumeScatter")
    scatter.phase = "HENYEY_GREENSTEIN"
    absorb = tree.nodes.new("ShaderNodeVolumeAbsorption")
    add = tree.nodes.new("ShaderNodeAddShader")
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    scatter.inputs["Color"].default_value = (*medium["albedo"], 1.0)
    scatter.inputs["Anisotropy"].default_value = medium["g"]
    absorb.inputs["Color"].default_value = (*medium["albedo"], 1.0)
    if density_attribute:
        attr = tree.nodes.new("ShaderNodeAttribute")
        attr.attribute_type = "GEOMETRY"
        attr.attribute_name = density_attribute
        scale = tree.nodes.new("ShaderNodeMath")
        scale.operation = "MULTIPLY"
        scale.inputs[1].default_value = medium["scale"]
        tree.links.new(attr.outputs["Fac"], scale.inputs[0])
        tree.links.new(scale.outputs["Value"], scatter.inputs["Density"])
        tree.links.new(scale.outputs["Value"], absorb.inputs["Density"])
    else:
        scatter.inputs["Density"].default_value = medium["sigma_t"]
        absorb.inputs["Density"].default_value = medium["sigma_t"]
    tree.links.new(scatter.outputs["Volume"], add.inputs[0])
    tree.links.new(absorb.outputs["Volume"], add.inputs[1])
    tree.links.new(add.outputs["Shader"], out.inputs["Volume"])
    return mat


def add_medium(scene, medium, vdb_path):
    if medium.get("camera_inside"):
        raise SystemExit("cycles_scene.py: a camera inside the medium has no Cycles translation here")
    if medium["type"] == "homogeneous":
        verts, faces = box_geometry(medium["min"], medium["max"])
        mesh_object(scene, "medium", verts, faces, volume_material(medium, None))
        return
    vol = bpy.data.volumes.new("medium")
    vol.filepath = vdb_path
    vol.grids.load()
    if "density" not in [g.name for g in vol.grids]:
        raise SystemExit(f"cycles_scene.py: {vdb_path} has no grid named density")
    vol.render.clipping = 0.0
    vol.render.precision = "FULL"
    vol.materials.append(volume_material(medium, "density"))
    obj = bpy.data.objects.new("medium", vol)
    scene.collection.objects.link(obj)


def build(spec, resolution, threads, guiding, seed, vdb_path, adaptive=False):
    """The whole Cycles scene for a table entry; returns the recorded render settings."""
    scene = reset()
    # The table's max_depth counts the camera vertex, as Mitsuba's does: brume and Cycles
    # get one less (scattering events / bounces).
    recorded = settings(scene, resolution, threads, guiding, seed, spec.get("max_depth", 64) - 1,
                        adaptive)
    add_camera(scene, spec["camera"])
    env = [x for x in spec["lights"] if x["type"] == "environment"]
    add_world(scene, env[0]["radiance"] if env else [0.0, 0.0, 0.0])
    for light in spec["lights"]:
        if light["type"] == "sun":
            add_sun(scene, light)
        elif light["type"] == "environment_map":
            add_world_map(scene, light["path"])
        elif light["type"] != "environment":
            raise SystemExit(f"cycles_scene.py: light type {light['type']!r} has no Cycles translation")
    for i, shape in enumerate(spec["shapes"]):
        add_shape(scene, i, shape)
    if spec.get("medium"):
        add_medium(scene, spec["medium"], vdb_path)
    return recorded


def render(scene, spp, out_path):
    """Renders `spp` samples into `out_path` (EXR); returns the wall seconds."""
    scene.cycles.samples = spp
    scene.render.filepath = str(out_path)
    t0 = time.perf_counter()
    bpy.ops.render.render(write_still=True)
    return time.perf_counter() - t0
