"""Renders one PNG per pose of a glTF file written by `ballast build`.

    blender -b --factory-startup --python-exit-code 1 --python docs/render/render_poses.py -- \
        build/t_shape.glb docs/images [--name t_shape] [--engine cycles|eevee] [--samples N]
        [--size 640x480]

The file's default scene lays every pose side by side, each a top-level group node named after
the pose (docs/cli.md, "The glTF file"). For each pose this script shows that group alone, on a
light grey floor at height 0, frames a camera on it (a three-quarter view from the front right,
a little above) and writes `OUTDIR/<name>-<pose slug>.png`, `<name>` being the file's stem unless
`--name` says otherwise and the slug the pose's name in lower case with every run of other
characters than letters and digits turned into one `-`.

The default engine is Cycles on the CPU, which renders without a display or a GPU. It denoises
when the Blender build has OpenImageDenoise (Debian's Blender 3.4 does not; it then renders more
samples instead). `--engine eevee` needs an OpenGL context (Blender falls back to surfaceless EGL
where there is no display, as with Mesa).
"""

import argparse
import json
import math
import re
import struct
import sys

import bpy
from mathutils import Vector

FLOOR_GREY = 0.4
BACKGROUND_GREY = 0.6
# Direction from the pose to the camera, Blender's axes after the import (+Z up, the file's
# front, glTF's +Z, is Blender's -Y): front right, 35 degrees round from the front, 20 degrees up.
AZIMUTH_DEG, ELEVATION_DEG = 35.0, 20.0
MARGIN = 1.12  # distance beyond the tightest framing


def arguments():
    argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else []
    parser = argparse.ArgumentParser(prog="render_poses.py")
    parser.add_argument("glb", help="a .glb file written by `ballast build`")
    parser.add_argument("out_dir", help="folder for the PNG files")
    parser.add_argument("--name", help="file name prefix (default: the .glb file's stem)")
    parser.add_argument("--engine", choices=["eevee", "cycles"], default="eevee")
    parser.add_argument("--samples", type=int, help="samples per pixel (default: by engine)")
    parser.add_argument("--size", default="640x480", help="WIDTHxHEIGHT in pixels")
    parser.add_argument("--pose", action="append", help="render only this pose (repeatable)")
    args = parser.parse_args(argv)
    if args.name is None:
        args.name = re.sub(r"\.glb$", "", args.glb.replace("\\", "/").rsplit("/", 1)[-1])
    width, height = args.size.lower().split("x")
    args.width, args.height = int(width), int(height)
    return args


def slug(name):
    return re.sub(r"[^a-z0-9]+", "-", name.lower()).strip("-") or "pose"


def clear_scene():
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)


def pose_names(path):
    """The names of the default scene's root nodes, the pose groups, in the file's order."""
    with open(path, "rb") as file:
        data = file.read()
    magic, _, _ = struct.unpack_from("<4sII", data, 0)
    length, kind = struct.unpack_from("<I4s", data, 12)
    if magic != b"glTF" or kind != b"JSON":
        raise SystemExit(f"render_poses: {path} is not a binary glTF file")
    gltf = json.loads(data[20 : 20 + length])
    scene = gltf["scenes"][gltf.get("scene", 0)]
    return [gltf["nodes"][n].get("name", f"node {n}") for n in scene["nodes"]]


def import_poses(path):
    """Imports the file and returns its pose groups, [(pose name, root object)], in file order."""
    # Blender 3.4's importer still names `numpy.bool`, which NumPy 1.24 (Debian 12's) removed.
    import numpy

    if "bool" not in numpy.__dict__:
        numpy.bool = bool
    before = set(bpy.data.objects)
    bpy.ops.import_scene.gltf(filepath=path)
    roots = {o.name: o for o in bpy.data.objects if o not in before and o.parent is None}
    groups = []
    for name in pose_names(path):
        # The importer names each object after its node, cut to Blender's 63 bytes.
        obj = roots.get(name) or next(
            (o for n, o in roots.items() if name.startswith(n) and len(n) >= 60), None
        )
        if obj is None:
            raise SystemExit(f"render_poses: no imported object for the pose {name!r}")
        groups.append((name, obj))
    return groups


def descendants(obj):
    found = [obj]
    for child in obj.children:
        found.extend(descendants(child))
    return found


def world_corners(objects):
    corners = []
    for obj in objects:
        if obj.type != "MESH":
            continue
        corners.extend(obj.matrix_world @ Vector(c) for c in obj.bound_box)
    return corners


def make_floor(scene):
    mesh = bpy.data.meshes.new("floor")
    s = 1.0
    mesh.from_pydata([(-s, -s, 0), (s, -s, 0), (s, s, 0), (-s, s, 0)], [], [(0, 1, 2, 3)])
    floor = bpy.data.objects.new("floor", mesh)
    scene.collection.objects.link(floor)
    material = bpy.data.materials.new("floor")
    material.use_nodes = True
    bsdf = material.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (FLOOR_GREY, FLOOR_GREY, FLOOR_GREY, 1.0)
    bsdf.inputs["Roughness"].default_value = 0.9
    bsdf.inputs["Specular"].default_value = 0.0
    mesh.materials.append(material)
    return floor


def make_world(scene):
    world = bpy.data.worlds.new("studio")
    world.use_nodes = True
    background = world.node_tree.nodes["Background"]
    background.inputs["Color"].default_value = (BACKGROUND_GREY,) * 3 + (1.0,)
    background.inputs["Strength"].default_value = 0.5
    scene.world = world


def towards(azimuth_deg, elevation_deg):
    """The unit vector pointing away from the pose, `azimuth_deg` round from the front (-Y)
    towards the right (+X) and `elevation_deg` up."""
    az, el = math.radians(azimuth_deg), math.radians(elevation_deg)
    return Vector((math.sin(az) * math.cos(el), -math.cos(az) * math.cos(el), math.sin(el)))


def make_lights(scene):
    # (name, azimuth, elevation, strength, casts a shadow): a key light from above the camera's
    # left, which alone casts shadows, and shadowless fills from the right, the camera and below,
    # in place of the ambient light of the sky (which would be noisy in Cycles).
    lights = [
        ("key", -25.0, 55.0, 3.0, True),
        ("fill", 110.0, 25.0, 0.9, False),
        ("front", AZIMUTH_DEG, ELEVATION_DEG, 0.5, False),
        ("under", 200.0, -35.0, 0.4, False),
    ]
    for name, azimuth, elevation, strength, shadow in lights:
        sun = bpy.data.lights.new(name, "SUN")
        sun.energy = strength
        sun.angle = math.radians(3.0)
        sun.use_shadow = shadow
        sun.cycles.cast_shadow = shadow
        obj = bpy.data.objects.new(name, sun)
        # A sun shines along its -Z.
        obj.rotation_euler = towards(azimuth, elevation).to_track_quat("Z", "Y").to_euler()
        scene.collection.objects.link(obj)


def make_camera(scene, width, height):
    data = bpy.data.cameras.new("camera")
    data.lens = 50.0
    data.sensor_fit = "AUTO"
    camera = bpy.data.objects.new("camera", data)
    scene.collection.objects.link(camera)
    scene.camera = camera
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.resolution_percentage = 100
    return camera


def set_engine(scene, engine, samples):
    render = scene.render
    render.image_settings.file_format = "PNG"
    render.image_settings.color_mode = "RGB"
    render.image_settings.color_depth = "8"
    render.image_settings.compression = 100
    render.film_transparent = False
    render.dither_intensity = 0.0  # dithering noise would double the PNG's size
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    if engine == "eevee":
        render.engine = "BLENDER_EEVEE"
        scene.eevee.taa_render_samples = samples or 32
        scene.eevee.use_soft_shadows = True
        scene.eevee.use_gtao = True
        scene.eevee.shadow_cascade_size = "2048"
        scene.eevee.gtao_distance = 0.01
        return
    render.engine = "CYCLES"
    cycles = scene.cycles
    cycles.device = "CPU"
    try:
        import _cycles

        denoise = bool(getattr(_cycles, "with_openimagedenoise", False))
    except ImportError:
        denoise = False
    cycles.use_denoising = denoise
    if denoise:
        cycles.denoiser = "OPENIMAGEDENOISE"
    cycles.samples = samples or (16 if denoise else 64)
    # The world lights nothing diffusely (the suns do, without noise), so the PNG stays small;
    # the steel balls still mirror it.
    scene.world.cycles_visibility.diffuse = False
    cycles.use_adaptive_sampling = True
    cycles.adaptive_threshold = 0.02
    cycles.max_bounces = 6
    cycles.diffuse_bounces = 0  # no light bounced off the floor: no noise from it
    cycles.glossy_bounces = 2
    cycles.transmission_bounces = 2
    cycles.transparent_max_bounces = 24
    cycles.sample_clamp_indirect = 2.0
    cycles.blur_glossy = 1.0
    cycles.caustics_reflective = False
    cycles.caustics_refractive = False
    render.filter_size = 1.5


def frame(camera, floor, corners, scene):
    lo = Vector([min(c[i] for c in corners) for i in range(3)])
    hi = Vector([max(c[i] for c in corners) for i in range(3)])
    centre = (lo + hi) / 2
    size = max((hi - lo).length, 1e-3)
    towards_camera = towards(AZIMUTH_DEG, ELEVATION_DEG)
    camera.rotation_euler = (-towards_camera).to_track_quat("-Z", "Y").to_euler()
    camera.location = centre + towards_camera * size * 3
    bpy.context.view_layer.update()
    fit, _ = camera.camera_fit_coords(
        bpy.context.evaluated_depsgraph_get(), [x for c in corners for x in c]
    )
    camera.location = centre + (Vector(fit) - centre) * MARGIN
    camera.data.clip_start = size * 0.01
    camera.data.clip_end = size * 100
    # EEVEE's sun shadows spread their maps over this distance from the camera: keep it near the
    # pose, or a small model's shadow falls between the texels.
    for light in bpy.data.lights:
        if light.type == "SUN":
            light.shadow_cascade_max_distance = (camera.location - centre).length + size * 4
            light.shadow_buffer_bias = 0.2
    # The floor spreads well beyond the view, under the pose.
    floor.location = (centre.x, centre.y, 0.0)
    floor.scale = (size * 40,) * 3


def render_pose(scene, groups, index, camera, floor, path):
    shown = set(descendants(groups[index][1]))
    for _, group in groups:
        for obj in descendants(group):
            obj.hide_render = obj not in shown
            obj.hide_viewport = obj not in shown
    corners = world_corners(shown)
    if not corners:
        print(f"render_poses: pose {groups[index][0]!r} has no mesh, skipped")
        return False
    frame(camera, floor, corners, scene)
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    print(f"render_poses: wrote {path}")
    return True


def main():
    args = arguments()
    clear_scene()
    scene = bpy.context.scene
    groups = import_poses(args.glb)
    if not groups:
        raise SystemExit(f"render_poses: no pose groups in {args.glb}")
    make_world(scene)
    set_engine(scene, args.engine, args.samples)
    make_lights(scene)
    floor = make_floor(scene)
    camera = make_camera(scene, args.width, args.height)
    wanted = set(args.pose or [name for name, _ in groups])
    for index, (name, _) in enumerate(groups):
        if name not in wanted:
            continue
        path = f"{args.out_dir.rstrip('/')}/{args.name}-{slug(name)}.png"
        render_pose(scene, groups, index, camera, floor, path)


main()
