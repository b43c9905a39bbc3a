#!/usr/bin/env python3
"""Measures what a Python step loop costs over the same loop in C++: the arm of urdf/arm.urdf
and the 210-box pyramid, each stepped with every body's position and orientation copied out
after every step. A measurement, not a test.

Times are CPU seconds of the stepping thread (on a shared machine wall time measures the other
jobs too), the fastest of several runs, the runs of C++ and Python interleaved. Steps vary by
tens of per cent from run to run on a loaded machine, more than the Python layer costs, so the
layer is also timed alone: the same loop with step(0), which goes through the whole binding
(argument passing, releasing the GIL, error check) and reads the states, but steps nothing.

usage: PYTHONPATH=build/python python3 tests/python/measure_overhead.py \\
           build/bin/pfx_python_reference [REPEATS]
"""
import subprocess
import sys
import time

import numpy as np

from pfx_scenes import ARM_URDF, build_arm, build_pyramid


def python_loop(world, steps, step_count=1):
    """Seconds per iteration of: step, then copy every position and orientation out."""
    positions = np.empty((world.num_bodies, 3), world.positions.dtype)
    orientations = np.empty((world.num_bodies, 4), positions.dtype)
    step = world.step
    start = time.thread_time()
    for _ in range(steps):
        step(step_count)
        np.copyto(positions, world.positions)
        np.copyto(orientations, world.orientations)
    return (time.thread_time() - start) / steps


def cpp_loop(program, scene_args, steps):
    out = subprocess.run([program, *scene_args, str(steps), "--time", "1"], check=True,
                         capture_output=True, text=True).stdout
    return float(out)


def main():
    program = sys.argv[1]
    repeats = int(sys.argv[2]) if len(sys.argv) > 2 else 9
    scenes = [("arm", ["arm", ARM_URDF], lambda: build_arm()[0], 2400),
              ("pyramid", ["pyramid"], build_pyramid, 300)]
    print("scene\tC++ us/step\tPython us/step\tend-to-end\tPython layer us/step\tlayer share")
    for name, args, build, steps in scenes:
        cpp, python, layer = [], [], []
        for _ in range(repeats):
            cpp.append(cpp_loop(program, args, steps))
            python.append(python_loop(build(), steps))
            layer.append(python_loop(build(), 20000, step_count=0))
        c, p, layer_cost = min(cpp), min(python), min(layer)
        print("%s\t%.1f\t%.1f\t%+.1f %%\t%.2f\t%.2f %%" %
              (name, 1e6 * c, 1e6 * p, 100 * (p / c - 1), 1e6 * layer_cost,
               100 * layer_cost / c))


if __name__ == "__main__":
    main()
