"""The scenes of pfx_python_reference.cpp built through the Python module, with the same
calls and values, and the states printed as that program prints them."""
import os

import numpy as np

import pfx

SOURCE_DIR = os.environ.get(
    "PFX_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
ARM_URDF = os.path.join(SOURCE_DIR, "urdf", "arm.urdf")


def build_arm(urdf=ARM_URDF):
    """The arm on a fixed base over a ground slab, gravity along -Z, its shoulder (joint_2)
    driven to 0.8 rad so that it swings over."""
    world = pfx.World(pfx.WorldParam(gravity=(0, 0, -9.80665), time_step=np.float32(1) / 240,
                                     enable_sleep=False))
    world.add_body(pfx.Shape.box((50, 50, 0.5)), pfx.BodyInit(mass=0, position=(0, 0, -0.5)))
    model = world.load_urdf(urdf, pfx.UrdfLoadParam(fixed_base=True))
    model.set_joint_command("joint_2", pfx.JointDrive.POSITION, 0.8)
    return world, model


def build_pyramid():
    """210 one-metre cubes of 1 kg in 20 layers on a ground slab (the benchmark's pyramid)."""
    world = pfx.World(pfx.WorldParam(enable_sleep=False))
    world.add_body(pfx.Shape.box((50, 0.5, 50)), pfx.BodyInit(mass=0, position=(0, -0.5, 0)))
    cube = pfx.Shape.box((0.5, 0.5, 0.5))
    base, pitch = 20, 1.02
    for layer in range(base):
        count = base - layer
        for i in range(count):
            world.add_body(cube, pfx.BodyInit(
                position=((i - 0.5 * (count - 1)) * pitch, 0.5 + layer, 0)))
    return world


def state_lines(world):
    """Each body's position, orientation (x, y, z, w), linear and angular velocity as the hex
    bits of its 13 floats, one line per body."""
    values = np.concatenate([world.positions, world.orientations, world.linear_velocities,
                             world.angular_velocities], axis=1)
    bits = values.view(np.uint32 if values.dtype == np.float32 else np.uint64)
    width = 2 * values.dtype.itemsize
    return [" ".join(format(int(b), "0%dx" % width) for b in row) for row in bits]
