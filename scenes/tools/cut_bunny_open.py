"""Cuts the base of scenes/bunny.obj open: removes the faces whose centroid lies below the
plane y = HEIGHT, drops the vertices no face uses and writes scenes/bunny-open.obj (vertex
lines copied verbatim). Checks that the result is one connected, manifold sheet with one
boundary loop. Usage: python3 scenes/tools/cut_bunny_open.py [HEIGHT]  (default 0.5)."""

import collections
import sys

SOURCE, TARGET = "scenes/bunny.obj", "scenes/bunny-open.obj"


def main(height):
    lines = open(SOURCE).read().splitlines()
    vertex_lines = [l for l in lines if l.startswith("v ")]
    positions = [tuple(map(float, l.split()[1:4])) for l in vertex_lines]
    faces = [[int(x.split("/")[0]) - 1 for x in l.split()[1:4]] for l in lines if l.startswith("f ")]
    kept = [f for f in faces if sum(positions[i][1] for i in f) / 3 >= height]
    half_edges = {(f[k], f[(k + 1) % 3]) for f in kept for k in range(3)}
    boundary = [(a, b) for (a, b) in half_edges if (b, a) not in half_edges]
    starts = collections.Counter(a for a, _ in boundary)
    assert all(c == 1 for c in starts.values()), "a vertex with two boundary gaps"
    following = dict(boundary)
    loop, x = 0, boundary[0][0]
    while True:
        x, loop = following[x], loop + 1
        if x == boundary[0][0]:
            break
    assert loop == len(boundary), "more than one boundary loop"
    used = sorted({i for f in kept for i in f})
    number = {v: k + 1 for k, v in enumerate(used)}
    valences = collections.Counter()
    neighbours = collections.defaultdict(set)
    for f in kept:
        for i in f:
            neighbours[i].update(set(f) - {i})
    for a, _ in boundary:
        valences[len(neighbours[a])] += 1
    header = [l for l in lines if l.startswith("#")]
    with open(TARGET, "w") as out:
        out.write("# bunny-open.obj: scenes/bunny.obj with its base cut open (a real scan with a boundary)\n")
        out.write(f"# {len(used)} vertices, {len(kept)} faces: the faces whose centroid lies below y = {height}\n")
        out.write(f"# removed; one boundary loop of {len(boundary)} edges, boundary valences "
                  + ", ".join(f"{n}: {c}" for n, c in sorted(valences.items())) + "\n")
        out.write("# Made by: python3 scenes/tools/cut_bunny_open.py " + str(height) + "\n")
        for l in header[4:]:
            out.write(l + "\n")
        for v in used:
            out.write(vertex_lines[v] + "\n")
        for f in kept:
            out.write("f %d %d %d\n" % tuple(number[i] for i in f))
    print(f"{TARGET}: {len(used)} vertices, {len(kept)} faces, {len(boundary)} boundary edges")


if __name__ == "__main__":
    main(float(sys.argv[1]) if len(sys.argv) > 1 else 0.5)
