#!/usr/bin/python3
"""Writes the Cornell box meshes of media/cornell/ as OBJ files.

The geometry is the measured Cornell box (Cornell Program of Computer Graphics, "Cornell Box
Data", https://www.graphics.cornell.edu/online/box/data.html): units are millimetres, the camera
looks along +z from (278, 273, -800). The light is lowered from the ceiling (y = 548.8) to
y = 548.7 so that the two do not coincide. Every quadrilateral is written as one OBJ face; the
reader splits it into two triangles. The BSDFs are two-sided, so only the light's winding matters:
its normal points down, into the box, the side it emits from.
"""
import os
import sys

QUADS = {
    "white": [  # floor, ceiling, and the two blocks
        [(552.8, 0, 0), (0, 0, 0), (0, 0, 559.2), (549.6, 0, 559.2)],
        [(556, 548.8, 0), (556, 548.8, 559.2), (0, 548.8, 559.2), (0, 548.8, 0)],
        # short block
        [(130, 165, 65), (82, 165, 225), (240, 165, 272), (290, 165, 114)],
        [(290, 0, 114), (290, 165, 114), (240, 165, 272), (240, 0, 272)],
        [(130, 0, 65), (130, 165, 65), (290, 165, 114), (290, 0, 114)],
        [(82, 0, 225), (82, 165, 225), (130, 165, 65), (130, 0, 65)],
        [(240, 0, 272), (240, 165, 272), (82, 165, 225), (82, 0, 225)],
        # tall block
        [(423, 330, 247), (265, 330, 296), (314, 330, 456), (472, 330, 406)],
        [(423, 0, 247), (423, 330, 247), (472, 330, 406), (472, 0, 406)],
        [(472, 0, 406), (472, 330, 406), (314, 330, 456), (314, 0, 456)],
        [(314, 0, 456), (314, 330, 456), (265, 330, 296), (265, 0, 296)],
        [(265, 0, 296), (265, 330, 296), (423, 330, 247), (423, 0, 247)],
    ],
    "back": [[(549.6, 0, 559.2), (0, 0, 559.2), (0, 548.8, 559.2), (556, 548.8, 559.2)]],
    "red": [[(552.8, 0, 0), (549.6, 0, 559.2), (556, 548.8, 559.2), (556, 548.8, 0)]],
    "green": [[(0, 0, 559.2), (0, 0, 0), (0, 548.8, 0), (0, 548.8, 559.2)]],
    "light": [[(343, 548.7, 227), (343, 548.7, 332), (213, 548.7, 332), (213, 548.7, 227)]],
}


def write(path, quads):
    with open(path, "w") as f:
        f.write("# Cornell box, written by tools/make_cornell.py\n")
        for q in quads:
            for v in q:
                f.write("v %g %g %g\n" % v)
        for i in range(len(quads)):
            f.write("f %d %d %d %d\n" % tuple(4 * i + k for k in range(1, 5)))


if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "media", "cornell")
    os.makedirs(out, exist_ok=True)
    for name, quads in QUADS.items():
        write(os.path.join(out, name + ".obj"), quads)
