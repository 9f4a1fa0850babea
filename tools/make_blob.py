#!/usr/bin/python3
"""Writes media/blob.ply: a closed, outward-facing, bunny-sized blob for the "milk in glass" scene.

A latitude-longitude sphere (one vertex per pole) whose radius is displaced by a few low-frequency
harmonics, r(θ, φ) = 1 + 0.18 sin²θ cos 2φ + 0.12 cos 3θ + 0.08 sin θ sin 3φ, so that it is smooth,
star-shaped (hence closed and without self-intersections) and visibly not a sphere. Written as
binary little-endian PLY with float positions, float per-vertex normals (of the smooth surface,
from the gradient of the implicit function |x| − r) and int32 triangle lists.
"""
import math
import os
import struct
import sys

import numpy as np

N_THETA, N_PHI = 64, 128


def radius(t, p):
    return (1 + 0.18 * math.sin(t) ** 2 * math.cos(2 * p) + 0.12 * math.cos(3 * t)
            + 0.08 * math.sin(t) * math.sin(3 * p))


def point(t, p):
    r = radius(t, p)
    return np.array([r * math.sin(t) * math.cos(p), r * math.sin(t) * math.sin(p), r * math.cos(t)])


def normal(t, p, h=1e-5):
    # The normal of the parametric surface: cross product of its partial derivatives
    # (central differences); at the poles the radial direction.
    if t < 1e-9 or t > math.pi - 1e-9:
        return np.array([0.0, 0.0, 1.0 if t < 1 else -1.0])
    dt = (point(t + h, p) - point(t - h, p)) / (2 * h)
    dp = (point(t, p + h) - point(t, p - h)) / (2 * h)
    n = np.cross(dt, dp)
    return n / np.linalg.norm(n)


def main(out):
    verts = [(0.0, 0.0)]
    for i in range(1, N_THETA):
        for j in range(N_PHI):
            verts.append((math.pi * i / N_THETA, 2 * math.pi * j / N_PHI))
    verts.append((math.pi, 0.0))
    south = len(verts) - 1

    def ring(i, j):
        return 1 + (i - 1) * N_PHI + (j % N_PHI)

    faces = []
    for j in range(N_PHI):
        faces.append((0, ring(1, j), ring(1, j + 1)))
        for i in range(1, N_THETA - 1):
            faces.append((ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)))
            faces.append((ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)))
        faces.append((ring(N_THETA - 1, j), south, ring(N_THETA - 1, j + 1)))
    P = [point(t, p) for t, p in verts]
    # Outward-facing check: the signed volume must be positive.
    vol = sum(np.dot(P[a], np.cross(P[b], P[c])) for a, b, c in faces) / 6
    assert vol > 0, vol
    with open(out, "wb") as f:
        f.write(("ply\nformat binary_little_endian 1.0\ncomment written by tools/make_blob.py\n"
                 "element vertex %d\nproperty float x\nproperty float y\nproperty float z\n"
                 "property float nx\nproperty float ny\nproperty float nz\n"
                 "element face %d\nproperty list uchar int vertex_indices\nend_header\n"
                 % (len(verts), len(faces))).encode())
        for (t, p), x in zip(verts, P):
            f.write(struct.pack("<6f", *x, *normal(t, p)))
        for a, b, c in faces:
            f.write(struct.pack("<B3i", 3, a, b, c))


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else
         os.path.join(os.path.dirname(__file__), "..", "media", "blob.ply"))
