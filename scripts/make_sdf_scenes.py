#!/usr/bin/env python3
"""Writes the meshes of scenes/sdf/: the bowl of sphere_in_bowl.yaml (a box with a sphere of
radius 0.6 m carved out of its top) as a triangle mesh, for the scene that compares the two.

The mesh is the carved sphere's surface inside the box (the bowl's inner face), facing the
sphere's centre (counter-clockwise seen from there), plus the box's top rim around it, all in
the bowl body's frame (box from z = -0.3 to 0.3, sphere centre at z = 0.5). Rings every 1.5
degrees of polar angle and 192 points around: chords of at most 16 mm, whose sag from the
sphere, c^2 / (8 R), stays under 0.06 mm.

Usage: scripts/make_sdf_scenes.py (writes scenes/sdf/meshes/bowl_inner.obj)."""
import math
import os

RADIUS = 0.6
CENTRE_Z = 0.5
TOP_Z = 0.3
HALF = 0.7
AROUND = 192
STEP_DEGREES = 1.5


def main():
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    out = os.path.join(root, "scenes", "sdf", "meshes", "bowl_inner.obj")
    # The sphere meets the top plane at polar angle acos((CENTRE_Z - TOP_Z) / RADIUS) from the
    # downward axis.
    rim_angle = math.acos((CENTRE_Z - TOP_Z) / RADIUS)
    rings = max(2, int(math.ceil(math.degrees(rim_angle) / STEP_DEGREES)))
    vertices = [(0.0, 0.0, CENTRE_Z - RADIUS)]
    for i in range(1, rings + 1):
        theta = rim_angle * i / rings
        for k in range(AROUND):
            phi = 2 * math.pi * k / AROUND
            r = RADIUS * math.sin(theta)
            vertices.append((r * math.cos(phi), r * math.sin(phi), CENTRE_Z - RADIUS * math.cos(theta)))
    faces = []
    ring = lambda i, k: 1 + (i - 1) * AROUND + (k % AROUND)
    # Seen from the centre above, counter-clockwise means clockwise seen from below (outside).
    for k in range(AROUND):
        faces.append((0, ring(1, k), ring(1, k + 1)))
    for i in range(1, rings):
        for k in range(AROUND):
            a, b = ring(i, k), ring(i, k + 1)
            c, d = ring(i + 1, k), ring(i + 1, k + 1)
            faces.append((a, c, d))
            faces.append((a, d, b))
    # The top face of the box around the hole: the rim ring joined to the square's corners.
    corners = [(HALF, HALF), (-HALF, HALF), (-HALF, -HALF), (HALF, -HALF)]
    first_corner = len(vertices)
    for x, y in corners:
        vertices.append((x, y, TOP_Z))
    for k in range(AROUND):
        phi = 2 * math.pi * (k + 0.5) / AROUND
        # The corner whose quadrant holds this slice.
        q = int(((phi - math.pi / 4) % (2 * math.pi)) // (math.pi / 2))
        corner = first_corner + q
        faces.append((ring(rings, k), corner, ring(rings, k + 1)))
    for q in range(4):
        # The triangle between two neighbouring corners and the rim point at their mid angle.
        mid = int(round((math.pi / 4 + math.pi / 2 * (q + 1)) / (2 * math.pi) * AROUND)) % AROUND
        faces.append((ring(rings, mid), first_corner + q, first_corner + (q + 1) % 4))
    os.makedirs(os.path.dirname(out), exist_ok=True)
    with open(out, "w") as f:
        f.write("# The inner face of the bowl of scenes/sdf/sphere_in_bowl.yaml and its top rim,\n")
        f.write("# written by scripts/make_sdf_scenes.py.\n")
        for v in vertices:
            f.write("v %.9f %.9f %.9f\n" % v)
        for a, b, c in faces:
            f.write("f %d %d %d\n" % (a + 1, b + 1, c + 1))
    print(out, len(vertices), "vertices", len(faces), "triangles")


if __name__ == "__main__":
    main()
