#!/usr/bin/env python3
"""Write the unit icosphere of a subdivision level as OBJ: the icosahedron, each face split
into four at its edge midpoints LEVEL times, every vertex pushed onto the unit sphere.
20 * 4^LEVEL faces (level 7: 327,680; level 8: 1,310,720), for scale measurements of the
renderer (results/benchmarks.md). Python 3 standard library only:

    python3 scenes/tools/icosphere.py 7 ico-7.obj
"""
import math
import sys


def main():
    level, out = int(sys.argv[1]), sys.argv[2]
    t = (1 + 5 ** 0.5) / 2
    corners = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
               (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
             (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
             (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]

    def on_sphere(p):
        length = math.sqrt(sum(c * c for c in p))
        return tuple(c / length for c in p)

    vertices = [on_sphere(p) for p in corners]
    for _ in range(level):
        midpoints = {}

        def midpoint(a, b):
            key = (min(a, b), max(a, b))
            if key not in midpoints:
                midpoints[key] = len(vertices)
                vertices.append(on_sphere(tuple((x + y) / 2 for x, y in zip(vertices[a], vertices[b]))))
            return midpoints[key]

        split = []
        for a, b, c in faces:
            ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
            split += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = split
    with open(out, "w") as f:
        f.write(f"# unit icosphere, level {level}: {len(vertices)} vertices, {len(faces)} faces\n")
        f.writelines("v %.17g %.17g %.17g\n" % p for p in vertices)
        f.writelines("f %d %d %d\n" % (a + 1, b + 1, c + 1) for a, b, c in faces)
    print(len(vertices), len(faces))


main()
