#!/usr/bin/env python3
"""Generates the example meshes: closed, outward-oriented, manifold triangle meshes in OBJ format.

Units are millimetres, Z is up. Run `python3 generate.py` (Python 3, standard library only) to
rewrite the OBJ files next to this script; the output is byte-for-byte the same on every run.

t_shape.obj -- the T shape of the paper (Figure 5)
    The T outline in the XZ plane, extruded 20 along Y (y in [-10, 10]):
    a stem 50 wide (x in [-25, 25]) and 30 tall (z in [0, 30]) under a bar 130 wide
    (x in [-65, 65]) and 10 tall (z in [30, 40]).
    Volume 20 * (50*30 + 130*10) = 56000. Centre of mass (0, 0, z_c) with
    z_c = (1500*15 + 1300*35) / 2800 = 170/7 = 24.29.
    - Upright (T), on the stem foot |x| <= 25: x_c = 0 is inside. Stands.
    - Upside down, on the bar top |x| <= 65: every point of the solid projects inside. Stands.
    - On a side: the convex hull's side face joins the stem foot edge A = (25, 0) to the bar end
      edge B = (65, 30) (it is 50 long: 40 across, 30 up). Lying on it, the model rests on the bar
      end and the stem foot; the support is that face. The centre of mass projects onto the
      line AB at (c - A).(B - A)/|B - A| = (-25*40 + 24.29*30)/50 = -5.43, that is 5.43 beyond the
      stem foot: the solid tips back onto its foot (a tilt of atan(5.43/34.43) = 9 degrees).
      Rotated 90 degrees onto the bar end alone (z in [30, 40]) it falls too: z_c = 24.29 < 30.
      Rotating the model by atan2(3, 4) = 36.87 degrees about +Y puts the +x side face on the
      ground (-36.87 degrees: the -x side face).
    Why so squat: with a bar 60 x 20 on a stem 20 x 60 the centre of mass projects 0.7 of the
    way along the side face, and the solid lies stably on its side. A solid T falls off its side
    face towards its foot only if z_c * stem height < stem width / 2 * bar overhang, which needs
    a short stem and a light bar (falling off past the bar end instead would leave it standing
    on the bar end).

sheared_cylinder.obj -- the sheared cylinder of the paper (Figure 2)
    A 64-sided circular cylinder of radius 15 and height 80 whose top disc is shifted by 40
    along +x: the bottom disc is centred at (0, 0, 0), the top disc at (40, 0, 80); both end
    caps are flat (horizontal). Volume 32 * 15^2 * sin(2 pi/64) * 80 = 56457.9 (a shear keeps
    the volume), centre of mass (20, 0, 40).
    Standing on the bottom needs the centre of mass above the bottom disc, |x| < 15; standing on
    the top needs it above the top disc, |x - 40| < 15. The vertical cylinders over the two discs
    are 40 - 2*15 = 10 apart, so no single centre of mass stands on both ends; the solid's
    (x = 20) stands on neither.

hinged_arm.obj -- an articulated model: objects `base` and `arm`
    base: a block x in [-30, 30], y in [-20, 20], z in [0, 20]; volume 48000, centroid
          (0, 0, 10).
    arm:  a bar x in [-30, 110], y in [-10, 10], z in [21, 37] (1 above the base); volume
          44800, centroid (40, 0, 29).
    The hinge is a vertical axis (+Z) through the pivot (-22, 0, 20) on top of the base.
    As modelled, the arm reaches out over the base along +x: the centre of mass is at
    x = 44800*40 / 92800 = 19.31, inside the base's footprint |x| <= 30. It stands.
    Turned 180 degrees about the hinge, the arm points the mirror way (x in [-154, -14],
    centroid x = -84): the centre of mass is at x = 44800*(-84) / 92800 = -40.55, 10.55 beyond
    the base's edge x = -30. It topples.
"""

import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))


class Solid:
    """A named triangle mesh: vertex positions and counter-clockwise (seen from outside)
    triangles indexing them, 0-based."""

    def __init__(self, name):
        self.name = name
        self.vertices = []
        self.triangles = []

    def vertex(self, x, y, z):
        self.vertices.append((x, y, z))
        return len(self.vertices) - 1


def extruded_y(name, outline, caps, y0, y1):
    """The prism over a polygon in the XZ plane, from y = y0 to y = y1 (y0 < y1).

    `outline` lists the polygon's (x, z) corners counter-clockwise, with x to the right and z up;
    `caps` triangulates it as index triples into `outline`, also counter-clockwise."""
    solid = Solid(name)
    front = [solid.vertex(x, y0, z) for x, z in outline]
    back = [solid.vertex(x, y1, z) for x, z in outline]
    for a, b, c in caps:
        # Counter-clockwise in (x, z) faces -y, the outside of the front cap.
        solid.triangles.append((front[a], front[b], front[c]))
        solid.triangles.append((back[a], back[c], back[b]))
    n = len(outline)
    for i in range(n):
        j = (i + 1) % n
        solid.triangles.append((front[i], back[j], front[j]))
        solid.triangles.append((front[i], back[i], back[j]))
    return solid


def box(name, x0, x1, y0, y1, z0, z1):
    """The box [x0, x1] x [y0, y1] x [z0, z1]."""
    outline = [(x0, z0), (x1, z0), (x1, z1), (x0, z1)]
    return extruded_y(name, outline, [(0, 1, 2), (0, 2, 3)], y0, y1)


def t_shape():
    outline = [
        (-25, 0), (25, 0), (25, 30), (65, 30),
        (65, 40), (-65, 40), (-65, 30), (-25, 30),
    ]
    caps = [
        (0, 1, 2), (0, 2, 7),  # the stem
        (7, 2, 4), (2, 3, 4), (7, 4, 5), (7, 5, 6),  # the bar
    ]
    return extruded_y("t_shape", outline, caps, -10, 10)


def sheared_cylinder(radius=15, height=80, shift=40, segments=64):
    solid = Solid("sheared_cylinder")
    angles = [2 * math.pi * i / segments for i in range(segments)]
    bottom = [solid.vertex(radius * math.cos(t), radius * math.sin(t), 0) for t in angles]
    top = [solid.vertex(shift + radius * math.cos(t), radius * math.sin(t), height) for t in angles]
    bottom_centre = solid.vertex(0, 0, 0)
    top_centre = solid.vertex(shift, 0, height)
    for i in range(segments):
        j = (i + 1) % segments
        solid.triangles.append((bottom_centre, bottom[j], bottom[i]))
        solid.triangles.append((top_centre, top[i], top[j]))
        solid.triangles.append((bottom[i], bottom[j], top[j]))
        solid.triangles.append((bottom[i], top[j], top[i]))
    return solid


def hinged_arm():
    return [
        box("base", -30, 30, -20, 20, 0, 20),
        box("arm", -30, 110, -10, 10, 21, 37),
    ]


def number(value):
    """Fixed six-decimal formatting, without a negative zero."""
    text = "%.6f" % value
    return "0.000000" if text == "-0.000000" else text


def write_obj(filename, solids, title):
    lines = ["# %s -- %s" % (filename, title),
             "# Generated by generate.py. Units: millimetres; Z up."]
    offset = 1
    for solid in solids:
        lines.append("o %s" % solid.name)
        lines.extend("v %s %s %s" % tuple(number(c) for c in v) for v in solid.vertices)
        lines.extend("f %d %d %d" % tuple(offset + i for i in t) for t in solid.triangles)
        offset += len(solid.vertices)
    with open(os.path.join(HERE, filename), "w", newline="\n") as out:
        out.write("\n".join(lines) + "\n")


def main():
    write_obj("t_shape.obj", [t_shape()], "the T shape (stem 50 x 30, bar 130 x 10, depth 20)")
    write_obj("sheared_cylinder.obj", [sheared_cylinder()],
              "sheared cylinder (radius 15, height 80, top shifted 40 along +x)")
    write_obj("hinged_arm.obj", hinged_arm(),
              "base and arm; hinge axis +Z through the pivot (-22, 0, 20)")


if __name__ == "__main__":
    main()
