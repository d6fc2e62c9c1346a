#!/usr/bin/env python3
"""Decimate a closed scanned triangle mesh to a small closed test mesh for scenes/.

This is how scenes/bunny-*.obj were made from the Stanford bunny. The input is the closed
1839-vertex, 3674-face bunny of the npm package `bunny` 1.0.1 (its `index.js` holds
`exports.positions=[[x,y,z],...]` and `exports.cells=[[a,b,c],...]`), or any OBJ file of
triangles. Python 3 standard library only:

    npm pack bunny@1.0.1 && tar xzf bunny-1.0.1.tgz
    python3 scenes/tools/decimate_scan.py package/index.js 1000 bunny-1k > scenes/bunny-1k.obj

The procedure (Garland & Heckbert 1997, "Surface simplification using quadric error metrics"):
1. Check that the input is closed, manifold and consistently oriented; turn it outward if its
   signed volume is negative.
2. Give each vertex the sum of the area-weighted plane quadrics of its faces.
3. Repeatedly collapse the edge whose merged vertex has the least quadric error, placed at the
   quadric's minimiser (or the best of the two ends and the midpoint when that is ill-posed or
   leaves the edge's neighbourhood), until the face count reaches the target. A collapse is
   skipped when it would
   - break the link condition (the ends share a neighbour other than the two opposite
     corners), so the surface stays a closed 2-manifold of the same genus;
   - give the merged vertex more than MAX_VALENCE edges, or an opposite corner fewer than 3;
   - turn a surviving face by more than MAX_TURN_DEGREES, or make its shape quality
     4·sqrt(3)·area / (sum of squared edges) fall below MIN_QUALITY (or below what it was).
4. Renumber the surviving vertices and faces in input order, round coordinates to 6 decimals
   (the precision of the source), check again, and write OBJ text with a header.

The result is deterministic: ties in the queue are broken by vertex numbers.
"""

import heapq
import json
import math
import re
import sys

MAX_VALENCE = 12
MIN_QUALITY = 0.2
MAX_TURN_DEGREES = 60.0
MAX_FLIP_BEND_DEGREES = 30.0
MIN_FLIP_QUALITY = 0.1
FLIP_SEED = 1994


def read_mesh(path):
    """Positions and faces from an npm-style `index.js` or an OBJ file."""
    text = open(path, encoding="utf-8").read()
    if path.endswith(".js"):
        positions = json.loads(re.search(r"exports\.positions\s*=\s*(\[.*?\]\])", text, re.S).group(1))
        faces = json.loads(re.search(r"exports\.cells\s*=\s*(\[.*?\]\])", text, re.S).group(1))
        return [tuple(map(float, p)) for p in positions], [tuple(f) for f in faces]
    positions, faces = [], []
    for line in text.splitlines():
        parts = line.split()
        if not parts:
            continue
        if parts[0] == "v":
            positions.append(tuple(float(x) for x in parts[1:4]))
        elif parts[0] == "f":
            corners = [int(c.split("/")[0]) - 1 for c in parts[1:]]
            if len(corners) != 3:
                sys.exit(f"face {len(faces)} has {len(corners)} corners; triangles only")
            faces.append(tuple(corners))
    return positions, faces


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def face_normal(p, q, r):
    """Twice-area normal of the triangle p q r."""
    return cross(sub(q, p), sub(r, p))


def quality(p, q, r):
    """4·sqrt(3)·area / (sum of squared edges): 1 for an equilateral triangle, 0 for a sliver."""
    twice_area = math.sqrt(dot(face_normal(p, q, r), face_normal(p, q, r)))
    squares = dot(sub(q, p), sub(q, p)) + dot(sub(r, q), sub(r, q)) + dot(sub(p, r), sub(p, r))
    return 2.0 * math.sqrt(3.0) * twice_area / squares if squares > 0.0 else 0.0


def check_closed_manifold(positions, faces):
    """Exits with a message unless every directed edge has exactly one opposite; returns chi."""
    directed = {}
    for f, (a, b, c) in enumerate(faces):
        for u, v in ((a, b), (b, c), (c, a)):
            if (u, v) in directed:
                sys.exit(f"edge {u}-{v} is used twice in the same direction (faces {directed[(u, v)]}, {f})")
            directed[(u, v)] = f
    for (u, v), f in directed.items():
        if (v, u) not in directed:
            sys.exit(f"edge {u}-{v} of face {f} has no opposite face: the mesh is open or misoriented")
    used = {v for face in faces for v in face}
    return len(used) - len(directed) // 2 + len(faces)


def signed_volume(positions, faces):
    return sum(dot(positions[a], cross(positions[b], positions[c])) for a, b, c in faces) / 6.0


def plane_quadric(p, q, r):
    """Area-weighted quadric (10 coefficients of the symmetric 4x4 matrix) of the face's plane."""
    n = face_normal(p, q, r)
    length = math.sqrt(dot(n, n))
    if length == 0.0:
        return [0.0] * 10
    area = 0.5 * length
    a, b, c = (x / length for x in n)
    d = -dot((a, b, c), p)
    return [area * x for x in (a * a, a * b, a * c, a * d, b * b, b * c, b * d, c * c, c * d, d * d)]


def quadric_error(k, x):
    a2, ab, ac, ad, b2, bc, bd, c2, cd, d2 = k
    return (a2 * x[0] * x[0] + 2 * ab * x[0] * x[1] + 2 * ac * x[0] * x[2] + 2 * ad * x[0]
            + b2 * x[1] * x[1] + 2 * bc * x[1] * x[2] + 2 * bd * x[1]
            + c2 * x[2] * x[2] + 2 * cd * x[2] + d2)


def quadric_minimiser(k):
    """Solves the 3x3 system of the quadric's minimum by Cramer's rule, or None if ill-posed."""
    a2, ab, ac, ad, b2, bc, bd, c2, cd, _ = k
    m = ((a2, ab, ac), (ab, b2, bc), (ac, bc, c2))
    rhs = (-ad, -bd, -cd)
    det = dot(m[0], cross(m[1], m[2]))
    scale = max(abs(x) for row in m for x in row)
    if scale == 0.0 or abs(det) < 1e-9 * scale ** 3:
        return None
    cols = list(zip(*m))

    def replaced(i):
        c = list(cols)
        c[i] = rhs
        rows = list(zip(*c))
        return dot(rows[0], cross(rows[1], rows[2]))

    return tuple(replaced(i) / det for i in range(3))


def decimate(positions, faces, target):
    positions = list(positions)
    faces = [list(f) for f in faces]
    alive = [True] * len(faces)
    incident = [set() for _ in positions]
    for f, face in enumerate(faces):
        for v in face:
            incident[v].add(f)
    quadrics = [[0.0] * 10 for _ in positions]
    for face in faces:
        k = plane_quadric(*(positions[v] for v in face))
        for v in face:
            quadrics[v] = [x + y for x, y in zip(quadrics[v], k)]
    stamp = [0] * len(positions)
    face_count = len(faces)

    def neighbours(v):
        return {w for f in incident[v] for w in faces[f] if w != v}

    def placement(u, v):
        k = [x + y for x, y in zip(quadrics[u], quadrics[v])]
        pu, pv = positions[u], positions[v]
        mid = tuple(0.5 * (a + b) for a, b in zip(pu, pv))
        candidates = [pu, pv, mid]
        x = quadric_minimiser(k)
        if x is not None and dot(sub(x, mid), sub(x, mid)) <= dot(sub(pu, pv), sub(pu, pv)):
            candidates.insert(0, x)
        best = min(candidates, key=lambda c: quadric_error(k, c))
        return max(quadric_error(k, best), 0.0), best

    heap = []

    def push(u, v):
        if u > v:
            u, v = v, u
        cost, _ = placement(u, v)
        heapq.heappush(heap, (cost, u, v, stamp[u], stamp[v]))

    for u in range(len(positions)):
        for v in neighbours(u):
            if u < v:
                push(u, v)

    def acceptable(u, v, x):
        shared = [f for f in incident[u] if v in faces[f]]
        if len(shared) != 2:
            return False
        opposite = {w for f in shared for w in faces[f] if w not in (u, v)}
        nu, nv = neighbours(u), neighbours(v)
        if nu & nv != opposite:
            return False
        if len(nu | nv) - 2 > MAX_VALENCE:
            return False
        if any(len(neighbours(w)) - 1 < 3 for w in opposite):
            return False
        for f in (incident[u] | incident[v]) - set(shared):
            old = [positions[w] for w in faces[f]]
            new = [x if w in (u, v) else positions[w] for w in faces[f]]
            n_old, n_new = face_normal(*old), face_normal(*new)
            len_old, len_new = math.sqrt(dot(n_old, n_old)), math.sqrt(dot(n_new, n_new))
            if len_new == 0.0 or dot(n_old, n_new) < math.cos(math.radians(MAX_TURN_DEGREES)) * len_old * len_new:
                return False
            if quality(*new) < min(MIN_QUALITY, quality(*old)):
                return False
        return True

    while face_count > target and heap:
        cost, u, v, su, sv = heapq.heappop(heap)
        if stamp[u] != su or stamp[v] != sv or not incident[u] or not incident[v]:
            continue
        _, x = placement(u, v)
        if not acceptable(u, v, x):
            continue
        for f in incident[u] & incident[v]:
            alive[f] = False
            face_count -= 1
            for w in faces[f]:
                incident[w].discard(f)
        for f in incident[v]:
            faces[f] = [u if w == v else w for w in faces[f]]
            incident[u].add(f)
        incident[v] = set()
        positions[u] = x
        quadrics[u] = [a + b for a, b in zip(quadrics[u], quadrics[v])]
        for w in neighbours(u) | {u}:
            stamp[w] += 1
        for w in neighbours(u):
            push(u, w)
            for z in neighbours(w):
                if z != u:
                    push(w, z)
    kept = sorted({w for f, face in enumerate(faces) if alive[f] for w in face})
    number = {old: new for new, old in enumerate(kept)}
    out_positions = [tuple(round(c, 6) + 0.0 for c in positions[w]) for w in kept]
    out_faces = [tuple(number[w] for w in face) for f, face in enumerate(faces) if alive[f]]
    return out_positions, out_faces


def spread_valences(positions, faces, flips, seed):
    """Seeded edge flips that make the valences more irregular, keeping the shape.

    An edge u-v with opposite corners a, b becomes a-b when that is not an edge yet, u and v keep
    at least 3 edges, a and b get at most MAX_VALENCE, the two new faces bend by at most
    MAX_FLIP_BEND_DEGREES against each other and against the old faces, keep a quality of at
    least MIN_FLIP_QUALITY, and the flip raises the sum of (valence - 6)^2 over its four
    vertices. Stops after `flips` flips or when no edge qualifies.
    """
    import random

    faces = [list(f) for f in faces]
    rng = random.Random(seed)
    cos_bend = math.cos(math.radians(MAX_FLIP_BEND_DEGREES))

    def unit_normal(face):
        n = face_normal(*(positions[w] for w in face))
        length = math.sqrt(dot(n, n))
        return tuple(x / length for x in n) if length > 0.0 else None

    done = 0
    while done < flips:
        edge_faces = {}
        for f, (a, b, c) in enumerate(faces):
            for u, v in ((a, b), (b, c), (c, a)):
                edge_faces[(u, v)] = f
        valence = {}
        for u, _ in edge_faces:
            valence[u] = valence.get(u, 0) + 1
        candidates = sorted((u, v) for u, v in edge_faces if u < v)
        rng.shuffle(candidates)
        flipped = False
        for u, v in candidates:
            f, g = edge_faces[(u, v)], edge_faces[(v, u)]
            a = next(w for w in faces[f] if w not in (u, v))
            b = next(w for w in faces[g] if w not in (u, v))
            if (a, b) in edge_faces or valence[u] <= 3 or valence[v] <= 3:
                continue
            if max(valence[a], valence[b]) >= MAX_VALENCE:
                continue
            gain = sum((valence[w] + d - 6) ** 2 - (valence[w] - 6) ** 2
                       for w, d in ((u, -1), (v, -1), (a, 1), (b, 1)))
            if gain <= 0:
                continue
            # faces[f] runs u -> v -> a (rotated), faces[g] runs v -> u -> b.
            new_f, new_g = [a, b, v], [b, a, u]
            old_f = unit_normal(faces[f])
            old_g = unit_normal(faces[g])
            nf, ng = unit_normal(new_f), unit_normal(new_g)
            if None in (nf, ng, old_f, old_g):
                continue
            if dot(nf, ng) < cos_bend or min(dot(n, o) for n in (nf, ng) for o in (old_f, old_g)) < cos_bend:
                continue
            if min(quality(*(positions[w] for w in face)) for face in (new_f, new_g)) < MIN_FLIP_QUALITY:
                continue
            faces[f], faces[g] = new_f, new_g
            done += 1
            flipped = True
            break
        if not flipped:
            break
    return [tuple(face) for face in faces], done


def valence_histogram(faces):
    edges = {tuple(sorted(e)) for a, b, c in faces for e in ((a, b), (b, c), (c, a))}
    valence = {}
    for a, b in edges:
        valence[a] = valence.get(a, 0) + 1
        valence[b] = valence.get(b, 0) + 1
    histogram = {}
    for n in valence.values():
        histogram[n] = histogram.get(n, 0) + 1
    return dict(sorted(histogram.items()))


def number_text(x):
    text = f"{x:.6f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def main():
    if len(sys.argv) not in (4, 5):
        sys.exit("usage: decimate_scan.py INPUT(.js|.obj) TARGET_FACES NAME [FLIPS]")
    path, target, name = sys.argv[1], int(sys.argv[2]), sys.argv[3]
    flips = int(sys.argv[4]) if len(sys.argv) == 5 else 0
    positions, faces = read_mesh(path)
    chi = check_closed_manifold(positions, faces)
    if signed_volume(positions, faces) < 0.0:
        faces = [(a, c, b) for a, b, c in faces]
    positions, faces = decimate(positions, faces, target)
    flipped = 0
    if flips:
        faces, flipped = spread_valences(positions, faces, flips, FLIP_SEED)
    if len(set(positions)) != len(positions):
        sys.exit("two vertices round to the same position")
    if check_closed_manifold(positions, faces) != chi:
        sys.exit("decimation changed the Euler characteristic")
    if signed_volume(positions, faces) <= 0.0:
        sys.exit("decimation turned the mesh inside out")
    worst = min(quality(*(positions[v] for v in face)) for face in faces)
    genus = (2 - chi) // 2
    histogram = valence_histogram(faces)
    print(f"# {name}.obj: the Stanford bunny, decimated and closed (a real scan)")
    print(f"# {len(positions)} vertices, {len(faces)} faces, genus {genus}")
    print("# valences " + ", ".join(f"{n}: {count}" for n, count in histogram.items()))
    print(f"# worst face quality 4*sqrt(3)*area/sum(edge^2) = {worst:.3f}")
    print("# Source: Stanford 3D Scanning Repository (Greg Turk and Marc Levoy, 1994), the closed")
    print("# 3674-face bunny of the npm package `bunny` 1.0.1 (Mikola Lysenko, declared public")
    print("# domain). Stanford's terms: free to use for research and to redistribute for free")
    print("# with credit to the Stanford Computer Graphics Laboratory; not for commercial products.")
    made_by = f"python3 scenes/tools/decimate_scan.py package/index.js {target} {name}"
    print(f"# Made by: {made_by}" + (f" {flips}" if flips else ""))
    print("# (quadric error edge collapses, Garland & Heckbert 1997; see that script)")
    if flips:
        print(f"# then {flipped} seeded edge flips (seed {FLIP_SEED}) that spread the valences; a flip")
        print("# only re-triangulates a nearly flat quad, the vertices are those of the decimation")
    for p in positions:
        print("v " + " ".join(number_text(c) for c in p))
    for a, b, c in faces:
        print(f"f {a + 1} {b + 1} {c + 1}")


if __name__ == "__main__":
    main()
