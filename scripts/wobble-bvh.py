#!/usr/bin/env python3
"""Writes an adversarial BVH for joint posture clustering's work bound (issue 29).

A chain of JOINTS joints, each wobbling slowly in all three axes with a small amplitude, so
that at ordinary thresholds (50 cm·degrees) the whole clip stays in a few very long
clusters: the key-posture search's hardest case (about m^1.8 in the cluster length).

  scripts/wobble-bvh.py FRAMES JOINTS OUT.bvh [--amplitude DEG] [--periods N]
"""
import argparse
import math

parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
parser.add_argument("frames", type=int)
parser.add_argument("joints", type=int)
parser.add_argument("out")
parser.add_argument("--amplitude", type=float, default=0.3, help="degrees, per axis")
parser.add_argument("--periods", type=float, default=3.0, help="slow periods over the clip")
args = parser.parse_args()

with open(args.out, "w") as f:
    f.write("HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0 0\n"
            "  CHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Xrotation\n")
    indent = "  "
    for j in range(1, args.joints):
        f.write(f"{indent}JOINT J{j}\n{indent}{{\n{indent}  OFFSET 0 10 0\n"
                f"{indent}  CHANNELS 3 Zrotation Yrotation Xrotation\n")
        indent += "  "
    f.write(f"{indent}End Site\n{indent}{{\n{indent}  OFFSET 0 10 0\n{indent}}}\n")
    for j in range(1, args.joints):
        indent = indent[:-2]
        f.write(f"{indent}}}\n")
    f.write(f"}}\nMOTION\nFrames: {args.frames}\nFrame Time: 0.0083333\n")
    a = args.amplitude
    w = 2.0 * math.pi * args.periods / max(1, args.frames)
    for t in range(args.frames):
        values = ["0 0 0"]
        for j in range(args.joints):
            phase = 0.7 * j
            # three incommensurate slow waves: the posture wanders on a 3D patch, not a path
            values.append(f"{a * math.cos(w * t + phase):.5f} {a * math.sin(1.618 * w * t + phase):.5f} "
                          f"{a * math.sin(2.414 * w * t + 2 * phase):.5f}")
        f.write(" ".join(values) + "\n")
