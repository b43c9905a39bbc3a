#!/usr/bin/env python3
"""Writes the collision and visual meshes of urdf/arm.urdf into this folder.

Run from anywhere: python3 urdf/meshes/make_meshes.py. Every mesh is closed and convex, in
metres, in the frame of the link that uses it (Z up, the link's joint at the origin), so a
convex hull of it is the mesh itself. Binary STL for most, Collada for the palm.

The Collada file says Y_UP although the geometry is Z-up: assimp turns a Z_UP scene onto Y
by a rotation of its root node while rviz drops that rotation, so Y_UP is the only tag both
read the same way (the geometry exactly as written).
"""
import math
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))


def box(x0, x1, y0, y1, z0, z1):
    """Eight corners and twelve outward (counter-clockwise) triangles."""
    v = [(x, y, z) for z in (z0, z1) for y in (y0, y1) for x in (x0, x1)]
    # Corner i: x bit 0, y bit 1, z bit 2.
    quads = [(0, 2, 3, 1), (4, 5, 7, 6),  # -z, +z
             (0, 1, 5, 4), (2, 6, 7, 3),  # -y, +y
             (0, 4, 6, 2), (1, 3, 7, 5)]  # -x, +x
    tris = []
    for a, b, c, d in quads:
        tris += [(a, b, c), (a, c, d)]
    return v, tris


def prism(radius, z0, z1, sides=8):
    """A regular prism about Z (a cylinder with `sides` flat sides), with outward triangles."""
    v = []
    for z in (z0, z1):
        for i in range(sides):
            angle = 2 * math.pi * (i + 0.5) / sides
            v.append((radius * math.cos(angle), radius * math.sin(angle), z))
    tris = []
    for i in range(sides):
        j = (i + 1) % sides
        tris += [(i, j, sides + j), (i, sides + j, sides + i)]
    for i in range(1, sides - 1):
        tris.append((0, i + 1, i))                    # bottom, facing -z
        tris.append((sides, sides + i, sides + i + 1))  # top, facing +z
    return v, tris


def normal(a, b, c):
    u = [b[k] - a[k] for k in range(3)]
    w = [c[k] - a[k] for k in range(3)]
    n = (u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0])
    length = math.sqrt(sum(x * x for x in n))
    return tuple(x / length for x in n)


def write_stl(name, mesh):
    vertices, triangles = mesh
    with open(os.path.join(HERE, name), "wb") as f:
        f.write(b"pfx arm mesh, written by make_meshes.py".ljust(80, b" "))
        f.write(struct.pack("<I", len(triangles)))
        for t in triangles:
            a, b, c = (vertices[i] for i in t)
            f.write(struct.pack("<3f", *normal(a, b, c)))
            for p in (a, b, c):
                f.write(struct.pack("<3f", *p))
            f.write(struct.pack("<H", 0))


def write_dae(name, mesh):
    vertices, triangles = mesh
    positions = " ".join("%g %g %g" % p for p in vertices)
    indices = " ".join("%d %d %d" % t for t in triangles)
    text = f"""<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset>
    <contributor><authoring_tool>pfx make_meshes.py</authoring_tool></contributor>
    <unit name="meter" meter="1"/>
    <up_axis>Y_UP</up_axis>
  </asset>
  <library_geometries>
    <geometry id="shape" name="shape">
      <mesh>
        <source id="shape-positions">
          <float_array id="shape-positions-array" count="{3 * len(vertices)}">{positions}</float_array>
          <technique_common>
            <accessor source="#shape-positions-array" count="{len(vertices)}" stride="3">
              <param name="X" type="float"/>
              <param name="Y" type="float"/>
              <param name="Z" type="float"/>
            </accessor>
          </technique_common>
        </source>
        <vertices id="shape-vertices">
          <input semantic="POSITION" source="#shape-positions"/>
        </vertices>
        <triangles count="{len(triangles)}">
          <input semantic="VERTEX" source="#shape-vertices" offset="0"/>
          <p>{indices}</p>
        </triangles>
      </mesh>
    </geometry>
  </library_geometries>
  <library_visual_scenes>
    <visual_scene id="scene" name="scene">
      <node id="shape-node" name="shape">
        <instance_geometry url="#shape"/>
      </node>
    </visual_scene>
  </library_visual_scenes>
  <scene>
    <instance_visual_scene url="#scene"/>
  </scene>
</COLLADA>
"""
    with open(os.path.join(HERE, name), "w") as f:
        f.write(text)


if __name__ == "__main__":
    write_stl("base.stl", prism(0.10, 0.0, 0.10))
    write_stl("shoulder.stl", prism(0.07, 0.0, 0.15))
    write_stl("upper_arm.stl", box(-0.04, 0.04, -0.04, 0.04, 0.0, 0.35))
    write_stl("forearm.stl", box(-0.03, 0.03, -0.03, 0.03, 0.0, 0.30))
    write_stl("wrist.stl", prism(0.04, 0.0, 0.08))
    write_dae("palm.dae", box(-0.06, 0.06, -0.035, 0.035, 0.0, 0.04))
    write_stl("finger.stl", box(-0.0075, 0.0075, -0.005, 0.005, 0.0, 0.05))
