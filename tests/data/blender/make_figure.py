"""Builds the jointed figure of figure_blender.glb in Blender and exports it with Blender's own
glTF exporter.

    blender -b --factory-startup --python-exit-code 1 \
        --python tests/data/blender/make_figure.py -- tests/data/blender/figure_blender.glb
    blender -b --factory-startup --python-exit-code 1 \
        --python tests/data/blender/make_figure.py -- \
        tests/data/blender/figure_blender_locrotscale.glb --key-location-scale

The figure is a toy about 15 cm tall, in Blender's metres with +Z up, facing -Y (Blender's front
view), so its left side is +X. It has six rigid parts, each a closed mesh object parented to an
empty (its joint) placed at its pivot:

    Hips (empty, the torso's joint, at the top of the legs)
      Torso       box
      Neck        empty at the top of the torso
        Head      UV sphere resting on the torso
      Shoulder.L  empty at the top of the left arm
        Arm.L     12-sided cylinder hanging down, 0.5 mm clear of the torso
      Shoulder.R
        Arm.R
      Hip.L       empty at the top of the left leg
        Leg.L     12-sided cylinder standing on the ground (z = 0)
      Hip.R
        Leg.R

Every part's object sits at its joint with an identity transform; its mesh is written in the
joint's frame. No part overlaps another at rest; the head and the legs touch the torso.

Three named animations, each an action per joint on an NLA track named after the animation (the
exporter merges the tracks of one name into one glTF animation):

    Wave   Shoulder.R, frames 1..25 (1 s at 24 fps), linear keys: the right arm raised 150 degrees
           out sideways.
    Reach  Shoulder.L and Shoulder.R, one key at frame 1: both arms straight forward.
    Kick   Hip.L, frames 1..13, Blender's default Bezier keys: the left leg swung 80 degrees
           forward.

Only the joints' rotations are keyed, so the exporter writes rotation channels only. With
`--key-location-scale` every key also holds the joint's rest location and a scale of 1, as
Blender's default keying set (Location, Rotation & Scale) keys them: the exporter then writes a
translation and a scale channel beside each rotation, sampled every frame like it. Their values
are decomposed from the sampled matrices, so a "constant" scale of 1 comes out as 1.0 or
0.99999994. The NLA is switched off on
every joint (use_nla = False), so that the file's rest pose is the figure at rest; the exporter
reads the tracks regardless. The parts carry no material.
"""

import math
import sys

import bmesh
import bpy
from mathutils import Matrix, Vector

FPS = 24

# Sizes in metres.
LEG_R, LEG_H, LEG_X = 0.009, 0.06, 0.011  # radius, length, offset from the middle
TORSO = (0.04, 0.024, 0.055)  # width (x), depth (y), height (z)
HEAD_R = 0.016
ARM_R, ARM_H = 0.006, 0.045
ARM_GAP = 0.0005  # between an arm and the torso
SHOULDER_DROP = 0.005  # shoulder joint below the top of the torso
SEGMENTS = 12


def arguments():
    """(output path, whether to key location and scale too) from the arguments after `--`."""
    argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else []
    key_all = "--key-location-scale" in argv
    paths = [a for a in argv if a != "--key-location-scale"]
    if len(paths) != 1:
        raise SystemExit(
            "usage: blender -b --factory-startup --python make_figure.py -- OUT.glb"
            " [--key-location-scale]"
        )
    return paths[0], key_all


def clear_scene():
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)
    for mesh in list(bpy.data.meshes):
        bpy.data.meshes.remove(mesh)
    for material in list(bpy.data.materials):
        bpy.data.materials.remove(material)
    scene = bpy.context.scene
    scene.render.fps = FPS
    scene.render.fps_base = 1.0
    scene.frame_start, scene.frame_end = 1, 250
    scene.frame_set(1)


def new_object(name, data, parent, location):
    obj = bpy.data.objects.new(name, data)
    bpy.context.scene.collection.objects.link(obj)
    if parent is not None:
        obj.parent = parent
        obj.matrix_parent_inverse = Matrix.Identity(4)
    obj.location = location
    return obj


def joint(name, parent, location):
    empty = new_object(name, None, parent, location)
    empty.empty_display_type = "PLAIN_AXES"
    empty.empty_display_size = 0.01
    return empty


def part(name, parent, build):
    """A mesh object at its joint's origin; `build(bm)` writes its geometry in the joint's frame."""
    bm = bmesh.new()
    build(bm)
    bmesh.ops.recalc_face_normals(bm, faces=bm.faces)
    mesh = bpy.data.meshes.new(name)
    bm.to_mesh(mesh)
    bm.free()
    return new_object(name, mesh, parent, (0.0, 0.0, 0.0))


def box(size, centre):
    def build(bm):
        matrix = Matrix.Translation(centre) @ Matrix.Diagonal((*size, 1.0))
        bmesh.ops.create_cube(bm, size=1.0, matrix=matrix)

    return build


def cylinder(radius, depth, centre):
    def build(bm):
        bmesh.ops.create_cone(
            bm,
            cap_ends=True,
            cap_tris=False,
            segments=SEGMENTS,
            radius1=radius,
            radius2=radius,
            depth=depth,
            matrix=Matrix.Translation(centre),
        )

    return build


def sphere(radius, centre):
    def build(bm):
        bmesh.ops.create_uvsphere(
            bm, u_segments=SEGMENTS, v_segments=8, radius=radius, matrix=Matrix.Translation(centre)
        )

    return build


def build_figure():
    w, d, h = TORSO
    hips = joint("Hips", None, (0.0, 0.0, LEG_H))
    part("Torso", hips, box((w, d, h), (0.0, 0.0, h / 2)))

    neck = joint("Neck", hips, (0.0, 0.0, h))
    part("Head", neck, sphere(HEAD_R, (0.0, 0.0, HEAD_R)))

    arm_x = w / 2 + ARM_GAP + ARM_R
    shoulders = {}
    for side, sign in (("L", 1.0), ("R", -1.0)):
        shoulder = joint(f"Shoulder.{side}", hips, (sign * arm_x, 0.0, h - SHOULDER_DROP))
        part(f"Arm.{side}", shoulder, cylinder(ARM_R, ARM_H, (0.0, 0.0, -ARM_H / 2)))
        shoulders[side] = shoulder

    legs = {}
    for side, sign in (("L", 1.0), ("R", -1.0)):
        hip = joint(f"Hip.{side}", hips, (sign * LEG_X, 0.0, 0.0))
        part(f"Leg.{side}", hip, cylinder(LEG_R, LEG_H, (0.0, 0.0, -LEG_H / 2)))
        legs[side] = hip
    return shoulders, legs


def add_animation(track_name, obj, keys, key_all, interpolation=None):
    """Puts an action keying `obj`'s rotation (Euler XYZ, degrees) at `keys` [(frame, (x, y, z))]
    on a new NLA track named `track_name`; with `key_all`, its rest location and a scale of 1 at
    the same frames too."""
    action = bpy.data.actions.new(f"{track_name}.{obj.name}")
    action.id_root = "OBJECT"
    curves = [("rotation_euler", [[math.radians(d) for d in degrees] for _, degrees in keys])]
    if key_all:
        curves.append(("location", [tuple(obj.location)] * len(keys)))
        curves.append(("scale", [(1.0, 1.0, 1.0)] * len(keys)))
    for path, values in curves:
        for axis in range(3):
            curve = action.fcurves.new(path, index=axis, action_group="Object Transforms")
            for (frame, _), value in zip(keys, values):
                point = curve.keyframe_points.insert(frame, value[axis])
                if interpolation is not None:
                    point.interpolation = interpolation
    data = obj.animation_data or obj.animation_data_create()
    track = data.nla_tracks.new()
    track.name = track_name
    track.strips.new(track_name, int(keys[0][0]), action)
    data.action = None
    data.use_nla = False


def animate(shoulders, legs, key_all):
    rest = (0.0, 0.0, 0.0)
    # The right arm (-X) swings out sideways and up: +150 degrees about +Y.
    wave = [(1, rest), (25, (0.0, 150.0, 0.0))]
    add_animation("Wave", shoulders["R"], wave, key_all, "LINEAR")
    # An arm hanging down (-Z) points forward (-Y) after -90 degrees about +X.
    for side in ("L", "R"):
        add_animation("Reach", shoulders[side], [(1, (-90.0, 0.0, 0.0))], key_all)
    # The left leg forward, Blender's default (Bezier) keys.
    add_animation("Kick", legs["L"], [(1, rest), (13, (-80.0, 0.0, 0.0))], key_all)


def export(path):
    # Blender 3.4's exporter (io_scene_gltf2 3.4.50). Every setting that matters is spelled out,
    # most at their defaults.
    bpy.ops.export_scene.gltf(
        filepath=path,
        export_format="GLB",
        export_yup=True,  # +Y up, as glTF says (Blender's -Y forward becomes glTF's +Z)
        export_apply=False,  # no modifiers to apply
        export_materials="NONE",
        export_normals=True,
        export_texcoords=False,
        export_colors=False,
        export_cameras=False,
        export_lights=False,
        export_extras=False,
        export_animations=True,
        export_frame_range=False,  # the actions' own frame ranges, not the scene's
        export_frame_step=1,
        export_force_sampling=True,  # sample every frame of each action (the default)
        export_optimize_animation_size=False,  # keep every sampled key
        export_nla_strips=True,  # one glTF animation per NLA track name
        export_current_frame=False,
        export_skins=False,  # rigid objects under empties: nothing is skinned
        export_morph=False,
        export_def_bones=False,
    )


def main():
    path, key_all = arguments()
    clear_scene()
    shoulders, legs = build_figure()
    animate(shoulders, legs, key_all)
    bpy.context.view_layer.update()
    export(path)
    print(f"make_figure: wrote {path}")


main()
