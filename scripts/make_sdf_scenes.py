#!/usr/bin/env python3
"""Writes the meshes and the pouring scene of scenes/sdf/: the bowl of sphere_in_bowl.yaml (a box
with a sphere of radius 0.6 m carved out of its top) as a triangle mesh, open (its inner face and
rim, for the scenes that compare a mesh bowl with the CSG one) and closed (the whole solid, for a
grid SDF), and pour_into_grid_bowl.yaml (50 mixed convex bodies poured into the grid SDF).

The mesh is the carved sphere's surface inside the box (the bowl's inner face), facing the
sphere's centre (counter-clockwise seen from there), plus the box's top rim around it, all in
the bowl body's frame (box from z = -0.3 to 0.3, sphere centre at z = 0.5). Rings every 1.5
degrees of polar angle and 192 points around: chords of at most 16 mm, whose sag from the
sphere, c^2 / (8 R), stays under 0.06 mm.

Usage: scripts/make_sdf_scenes.py (writes scenes/sdf/meshes/bowl_inner.obj, bowl_closed.obj and
scenes/sdf/pour_into_grid_bowl.yaml)."""
import math
import os
import random

RADIUS = 0.6
CENTRE_Z = 0.5
TOP_Z = 0.3
HALF = 0.7
AROUND = 192
STEP_DEGREES = 1.5


def write_obj(path, header, vertices, faces):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(header)
        for v in vertices:
            f.write("v %.9f %.9f %.9f\n" % v)
        for a, b, c in faces:
            f.write("f %d %d %d\n" % (a + 1, b + 1, c + 1))
    print(path, len(vertices), "vertices", len(faces), "triangles")


def bowl(closed):
    """The bowl's vertices and faces; closed adds the box's four sides and bottom."""
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
    if closed:
        # The sides and the bottom, counter-clockwise seen from outside.
        low = len(vertices)
        for x, y in corners:
            vertices.append((x, y, -TOP_Z))
        for q in range(4):
            a, b = first_corner + q, first_corner + (q + 1) % 4
            c, d = low + q, low + (q + 1) % 4
            faces.append((a, c, d))
            faces.append((a, d, b))
        faces.append((low, low + 3, low + 2))
        faces.append((low, low + 2, low + 1))
    return vertices, faces


def pour_scene():
    """50 bodies over the grid bowl, five kinds in turn, on a jittered 5 x 5 x 2 lattice."""
    rng = random.Random(7)
    lines = [
        "# 50 mixed convex bodies (spheres, boxes, capsules, cylinders, hulls) poured into a bowl",
        "# given as a grid SDF of a closed triangle mesh (meshes/bowl_closed.obj, the solid of",
        "# sphere_in_bowl.yaml's CSG bowl). Written by scripts/make_sdf_scenes.py.",
        "world:",
        "  dt: 0.004166666666666667",
        "  duration: 10.0",
        "materials:",
        "  default: {friction: 0.5}",
        "bodies:",
        "  - name: floor",
        "    shape: {type: plane}",
        "    static: true",
        "  - name: bowl",
        "    static: true",
        "    shape: {type: sdf, sdf: {grid: {file: meshes/bowl_closed.obj, cell: 0.02}}}",
        "    position: [0, 0, 0.3]",
    ]
    kinds = [
        "{type: sphere, radius: 0.06}",
        "{type: box, half_extents: [0.06, 0.045, 0.035]}",
        "{type: capsule, radius: 0.035, half_length: 0.05}",
        "{type: cylinder, radius: 0.05, half_length: 0.03}",
        "{type: hull, points: [[0.06, 0, -0.04], [-0.03, 0.052, -0.04], [-0.03, -0.052, -0.04], [0, 0, 0.06]]}",
    ]
    n = 0
    for layer in range(2):
        for i in range(5):
            for j in range(5):
                x = -0.3 + 0.15 * i + rng.uniform(-0.02, 0.02)
                y = -0.3 + 0.15 * j + rng.uniform(-0.02, 0.02)
                z = 0.75 + 0.18 * layer + rng.uniform(0, 0.03)
                lines += [
                    "  - name: body%d" % n,
                    "    shape: %s" % kinds[n % len(kinds)],
                    "    density: 800",
                    "    position: [%.4f, %.4f, %.4f]" % (x, y, z),
                ]
                n += 1
    lines.append("camera: {position: [2.2, -2.2, 1.8], target: [0, 0, 0.3], fov: 40}")
    return "\n".join(lines) + "\n"


def main():
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    meshes = os.path.join(root, "scenes", "sdf", "meshes")
    vertices, faces = bowl(False)
    write_obj(os.path.join(meshes, "bowl_inner.obj"),
              "# The inner face of the bowl of scenes/sdf/sphere_in_bowl.yaml and its top rim,\n"
              "# written by scripts/make_sdf_scenes.py.\n", vertices, faces)
    vertices, faces = bowl(True)
    write_obj(os.path.join(meshes, "bowl_closed.obj"),
              "# The solid bowl of scenes/sdf/sphere_in_bowl.yaml (a box minus a sphere), closed,\n"
              "# written by scripts/make_sdf_scenes.py.\n", vertices, faces)
    with open(os.path.join(root, "scenes", "sdf", "pour_into_grid_bowl.yaml"), "w") as f:
        f.write(pour_scene())


if __name__ == "__main__":
    main()
