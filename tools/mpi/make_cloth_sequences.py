#!/usr/bin/env python3
"""Writes folding-cloth frame sequences (binary little-endian PLY) for measuring `mccd batch`:
an N x N grid folded about its middle line through itself, with a ripple, so that most steps
after the first third have contacts. One folder per sequence and a manifest.

    make_cloth_sequences.py OUT_DIR --count 6 --grid 60 --frames 24
"""
import argparse, math, os, struct

def frame(n, k, frames, phase):
    a = math.pi * 1.15 * k / (frames - 1)  # fold angle: past flat-on-itself by the end
    verts = []
    for j in range(n + 1):
        for i in range(n + 1):
            x, y = i / n - 0.5, j / n
            z = 0.01 * math.sin(6 * x + 4 * y + phase + 0.3 * k)
            if x > 0:  # the right half turns about the line x = 0
                x, z = x * math.cos(a) - z * math.sin(a), x * math.sin(a) + z * math.cos(a) + 0.002
            verts.append((x, y, z))
    return verts

def faces(n):
    out = []
    for j in range(n):
        for i in range(n):
            v = j * (n + 1) + i
            out += [(v, v + 1, v + n + 2), (v, v + n + 2, v + n + 1)]
    return out

def write_ply(path, verts, tris):
    with open(path, "wb") as f:
        f.write(("ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty float x\nproperty float y\n"
                 "property float z\nelement face %d\nproperty list uchar int vertex_indices\nend_header\n"
                 % (len(verts), len(tris))).encode())
        f.write(b"".join(struct.pack("<3f", *v) for v in verts))
        f.write(b"".join(struct.pack("<B3i", 3, *t) for t in tris))

ap = argparse.ArgumentParser()
ap.add_argument("out")
ap.add_argument("--count", type=int, default=6)
ap.add_argument("--grid", type=int, default=60)
ap.add_argument("--frames", type=int, default=24)
a = ap.parse_args()
os.makedirs(a.out, exist_ok=True)
with open(os.path.join(a.out, "list.txt"), "w") as m:
    for s in range(a.count):
        n = a.grid + 4 * s  # sizes differ: the batch hands the largest out first
        d = os.path.join(a.out, "cloth%d" % s)
        os.makedirs(d, exist_ok=True)
        tris = faces(n)
        for k in range(a.frames):
            write_ply(os.path.join(d, "frame%03d.ply" % k), frame(n, k, a.frames, s), tris)
        m.write("cloth%d/frame%%03d.ply\n" % s)
