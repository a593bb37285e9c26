#!/usr/bin/env python3
"""Writes walker.glb: a rigged, animated humanoid for trample's tests and scenes.

Python 3 standard library only. Run from anywhere:

    python3 scenes/meshes/make_walker.py            # writes scenes/meshes/walker.glb

The output is deterministic (same bytes on every run).

The character ("mannequin"), 1.67 m tall, stands on y = 0 facing +z (glTF's
forward), left side on +x. It is six closed tubes that never touch one
another, so the whole mesh is closed and "inside" is well defined for the
ray-parity test even as the limbs swing (a union of overlapping closed parts
would count the overlaps as outside):

- torso: an elliptic tube with rounded ends, skinned to hips (bottom) and
  spine (top), blended at the waist;
- head: a sphere on the head bone, 1 cm above the torso (no neck);
- two legs: one tube each from the hip down the thigh and shin, bending
  forward at the ankle into the foot, skinned to thigh / shin / foot with
  smooth blends at the knee and the ankle;
- two arms: one tube each, upper arm / forearm blended at the elbow.

Skeleton (13 joints; rest rotations are the identity, so the inverse bind
matrices are translations): hips (root, pelvis centre 0.95 m up) > spine >
head; hips > thigh_l > shin_l > foot_l and the same on the right; spine >
upper_arm_l > forearm_l and the same on the right.

Animation "walk": a 1.0 s loop, in place (the scene path moves the root):
thighs swing +-25 deg in opposition, knees flex up to 60 deg in mid-swing,
the ankles keep the soles level, arms swing +-20 deg against the legs with the elbows bent,
the hips bob 6 cm and twist +-5 deg, the spine counter-twists. 25 keys per
channel (the last equals the first), LINEAR. Stride: about 0.7 m per step,
two steps a loop, so it matches a root speed of about 1.4 m/s.
"""

import json
import math
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "walker.glb")

# ---------------------------------------------------------------- skeleton
# name, parent, rest translation relative to the parent (metres)
JOINTS = [
    ("hips", None, (0.0, 0.95, 0.0)),
    ("spine", "hips", (0.0, 0.25, 0.0)),
    ("head", "spine", (0.0, 0.35, 0.0)),
    ("thigh_l", "hips", (0.10, -0.03, 0.0)),
    ("shin_l", "thigh_l", (0.0, -0.42, 0.0)),
    ("foot_l", "shin_l", (0.0, -0.40, 0.0)),
    ("thigh_r", "hips", (-0.10, -0.03, 0.0)),
    ("shin_r", "thigh_r", (0.0, -0.42, 0.0)),
    ("foot_r", "shin_r", (0.0, -0.40, 0.0)),
    ("upper_arm_l", "spine", (0.21, 0.25, 0.0)),
    ("forearm_l", "upper_arm_l", (0.0, -0.28, 0.0)),
    ("upper_arm_r", "spine", (-0.21, 0.25, 0.0)),
    ("forearm_r", "upper_arm_r", (0.0, -0.28, 0.0)),
]
INDEX = {name: i for i, (name, _, _) in enumerate(JOINTS)}


def world_position(name):
    x = y = z = 0.0
    while name is not None:
        _, parent, (tx, ty, tz) = JOINTS[INDEX[name]]
        x, y, z = x + tx, y + ty, z + tz
        name = parent
    return (x, y, z)


# ---------------------------------------------------------------- geometry
def smoothstep(a, b, x):
    if b <= a:
        return 1.0 if x >= b else 0.0
    t = min(1.0, max(0.0, (x - a) / (b - a)))
    return t * t * (3.0 - 2.0 * t)


def blend(s, bounds):
    """Weights of consecutive bones along a tube: bounds = [(centre, half width), ...]
    between bone k and k+1. Returns {bone_k: w} with at most two bones."""
    weights = [1.0]
    for centre, half in bounds:
        w = smoothstep(centre - half, centre + half, s)
        last = weights[-1]
        weights[-1] = last * (1.0 - w)
        weights.append(last * w)
    return weights


class Mesh:
    def __init__(self):
        self.positions = []
        self.influences = []  # list of [(joint, weight)]
        self.triangles = []

    def vertex(self, p, influence):
        self.positions.append(p)
        self.influences.append(influence)
        return len(self.positions) - 1


def add(a, b):
    return tuple(x + y for x, y in zip(a, b))


def scale(a, s):
    return tuple(x * s for x in a)


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def norm(a):
    length = math.sqrt(sum(x * x for x in a))
    return tuple(x / length for x in a)


def tube(mesh, rings, segments, start_cap, end_cap, cap_rings=6):
    """A closed tube. rings: [(centre, tangent, rx, rz, influence)] along a
    centreline in a plane x = const; the cross-section is an ellipse of half
    axes rx (along x) and rz (along tangent x X, in the plane). Rounded caps of
    length start_cap / end_cap close the ends."""
    lateral = (1.0, 0.0, 0.0)

    def ring_points(centre, tangent, rx, rz):
        e2 = norm(cross(tangent, lateral))
        return [
            add(centre, add(scale(lateral, rx * math.cos(2 * math.pi * k / segments)),
                            scale(e2, rz * math.sin(2 * math.pi * k / segments))))
            for k in range(segments)
        ]

    # Cap rings before the first and after the last ring.
    c0, t0, rx0, rz0, inf0 = rings[0]
    c1, t1, rx1, rz1, inf1 = rings[-1]
    full = []
    for j in range(cap_rings, 0, -1):
        a = (math.pi / 2) * j / (cap_rings + 1)
        full.append((add(c0, scale(t0, -start_cap * math.sin(a))), t0,
                     rx0 * math.cos(a), rz0 * math.cos(a), inf0))
    full.extend(rings)
    for j in range(1, cap_rings + 1):
        a = (math.pi / 2) * j / (cap_rings + 1)
        full.append((add(c1, scale(t1, end_cap * math.sin(a))), t1,
                     rx1 * math.cos(a), rz1 * math.cos(a), inf1))
    ids = []
    for centre, tangent, rx, rz, inf in full:
        ids.append([mesh.vertex(p, inf) for p in ring_points(centre, tangent, rx, rz)])
    first = mesh.vertex(add(c0, scale(t0, -start_cap)), inf0)
    last = mesh.vertex(add(c1, scale(t1, end_cap)), inf1)
    n = segments
    tris = []
    for r in range(len(ids) - 1):
        a, b = ids[r], ids[r + 1]
        for k in range(n):
            k1 = (k + 1) % n
            tris.append((a[k], a[k1], b[k1]))
            tris.append((a[k], b[k1], b[k]))
    for k in range(n):
        k1 = (k + 1) % n
        tris.append((first, ids[0][k1], ids[0][k]))
        tris.append((last, ids[-1][k], ids[-1][k1]))
    # Outward winding: flip the part if its signed volume is negative.
    volume = 0.0
    for i, j, k in tris:
        volume += sum(x * y for x, y in zip(mesh.positions[i], cross(mesh.positions[j], mesh.positions[k])))
    if volume < 0:
        tris = [(i, k, j) for i, j, k in tris]
    mesh.triangles.extend(tris)


def polyline(points, step):
    """Points along a polyline every ~step metres: [(point, tangent, s)]."""
    out = []
    s0 = 0.0
    for (a, b) in zip(points, points[1:]):
        d = tuple(y - x for x, y in zip(a, b))
        length = math.sqrt(sum(x * x for x in d))
        n = max(1, round(length / step))
        t = norm(d)
        for i in range(n):
            f = i / n
            out.append((add(a, scale(d, f)), t, s0 + f * length))
        s0 += length
    out.append((points[-1], t, s0))
    return out


def leg(mesh, side):
    sx = 0.10 * side
    hip = (sx, 0.92, 0.0)
    knee = (sx, 0.50, 0.0)
    ankle = (sx, 0.10, 0.0)
    # Ankle bend: an arc of radius 0.06 from straight down to forward.
    bend = [(sx, 0.10 - 0.06 * math.sin(a), 0.06 - 0.06 * math.cos(a))
            for a in [math.pi / 2 * i / 6 for i in range(1, 7)]]
    toe = (sx, 0.04, 0.20)
    pts = polyline([hip, knee, ankle] + bend + [toe], 0.02)
    suffix = "_l" if side > 0 else "_r"
    bones = [INDEX["thigh" + suffix], INDEX["shin" + suffix], INDEX["foot" + suffix]]
    rings = []
    for p, t, s in pts:
        # Radius along the leg: thigh 0.07 -> knee 0.05 -> calf 0.05 -> ankle 0.035.
        if s < 0.42:
            r = 0.07 - 0.02 * s / 0.42
        elif s < 0.82:
            r = 0.05 - 0.015 * smoothstep(0.6, 0.82, s)
        else:
            r = 0.035
        rz = r
        if s > 0.9:  # the foot: a little wider than tall
            rx, rz = 0.045, 0.032
        else:
            rx = r
        w = blend(s, [(0.42, 0.07), (0.82, 0.04)])
        inf = [(b, x) for b, x in zip(bones, w) if x > 1e-6]
        rings.append((p, t, rx, rz, inf))
    tube(mesh, rings, 14, 0.07, 0.03)


def arm(mesh, side):
    sx = 0.21 * side
    shoulder = (sx, 1.45, 0.0)
    elbow = (sx, 1.17, 0.0)
    hand = (sx, 0.86, 0.0)
    pts = polyline([shoulder, elbow, hand], 0.02)
    suffix = "_l" if side > 0 else "_r"
    bones = [INDEX["upper_arm" + suffix], INDEX["forearm" + suffix]]
    rings = []
    for p, t, s in pts:
        r = 0.045 - 0.012 * smoothstep(0.0, 0.5, s) + 0.006 * smoothstep(0.5, 0.59, s)
        w = blend(s, [(0.28, 0.05)])
        rings.append((p, t, r, r, [(b, x) for b, x in zip(bones, w) if x > 1e-6]))
    tube(mesh, rings, 12, 0.045, 0.035)


def torso(mesh):
    pts = polyline([(0.0, 1.05, 0.0), (0.0, 1.50, 0.0)], 0.025)
    rings = []
    for p, t, s in pts:
        y = p[1]
        rx = 0.15 + 0.01 * math.sin(math.pi * (y - 1.05) / 0.45)
        rz = 0.10
        w = blend(s, [(0.18, 0.06)])
        inf = [(b, x) for b, x in zip([INDEX["hips"], INDEX["spine"]], w) if x > 1e-6]
        rings.append((p, t, rx, rz, inf))
    tube(mesh, rings, 24, 0.06, 0.05)


def head(mesh, stacks=14, slices=24, r=0.11):
    c = (0.0, 1.67, 0.0)
    inf = [(INDEX["head"], 1.0)]
    top = mesh.vertex(add(c, (0, r, 0)), inf)
    bottom = mesh.vertex(add(c, (0, -r, 0)), inf)
    rows = []
    for i in range(1, stacks):
        a = math.pi * i / stacks
        rows.append([mesh.vertex(add(c, (r * math.sin(a) * math.cos(2 * math.pi * k / slices),
                                         r * math.cos(a),
                                         r * math.sin(a) * math.sin(2 * math.pi * k / slices))), inf)
                     for k in range(slices)])
    for k in range(slices):
        k1 = (k + 1) % slices
        mesh.triangles.append((top, rows[0][k1], rows[0][k]))
        mesh.triangles.append((bottom, rows[-1][k], rows[-1][k1]))
    for a, b in zip(rows, rows[1:]):
        for k in range(slices):
            k1 = (k + 1) % slices
            mesh.triangles.append((a[k], a[k1], b[k1]))
            mesh.triangles.append((a[k], b[k1], b[k]))


# ---------------------------------------------------------------- animation
KEYS = 25
PERIOD = 1.0


def quat_axis(axis, degrees):
    a = math.radians(degrees) / 2
    s = math.sin(a)
    return (axis[0] * s, axis[1] * s, axis[2] * s, math.cos(a))


def forward(degrees):
    """Rotation that swings a limb hanging along -y forward (+z) by degrees."""
    return quat_axis((1.0, 0.0, 0.0), -degrees)


def walk_channels():
    times = [PERIOD * i / (KEYS - 1) for i in range(KEYS)]
    ch = {}

    def put(joint, path, fn):
        ch[(joint, path)] = [fn(2 * math.pi * t / PERIOD) for t in times]

    def thigh(p):  # forward swing, degrees
        return 25 * math.sin(p)

    def knee(p):  # flexion, degrees: most in mid-swing, when the thigh passes 0
        return 5 + 55 * max(0.0, math.cos(p)) ** 1.5

    for suffix, phase in (("_l", 0.0), ("_r", math.pi)):
        put("thigh" + suffix, "rotation", lambda p, ph=phase: forward(thigh(p + ph)))
        put("shin" + suffix, "rotation", lambda p, ph=phase: forward(-knee(p + ph)))
        # The sole stays level: the ankle undoes the thigh's and the knee's tilt.
        put("foot" + suffix, "rotation",
            lambda p, ph=phase: forward(knee(p + ph) - thigh(p + ph)))
        put("upper_arm" + suffix, "rotation", lambda p, ph=phase: forward(-20 * math.sin(p + ph)))
        put("forearm" + suffix, "rotation",
            lambda p, ph=phase: forward(15 + 10 * max(0.0, -math.sin(p + ph))))
    put("hips", "translation", lambda p: (0.0, 0.95 - 0.03 + 0.03 * math.cos(2 * p), 0.0))
    put("hips", "rotation", lambda p: quat_axis((0.0, 1.0, 0.0), 5 * math.sin(p)))
    put("spine", "rotation", lambda p: quat_axis((0.0, 1.0, 0.0), -8 * math.sin(p)))
    # Exact loop: the last key is the first.
    for key in ch:
        ch[key][-1] = ch[key][0]
    return times, ch


# ---------------------------------------------------------------- glTF
class Bin:
    def __init__(self):
        self.data = bytearray()
        self.views = []
        self.accessors = []

    def view(self, raw, target=None):
        while len(self.data) % 4:
            self.data.append(0)
        v = {"buffer": 0, "byteOffset": len(self.data), "byteLength": len(raw)}
        if target:
            v["target"] = target
        self.data.extend(raw)
        self.views.append(v)
        return len(self.views) - 1

    def accessor(self, raw, component, count, kind, target=None, minmax=None):
        a = {"bufferView": self.view(raw, target), "componentType": component,
             "count": count, "type": kind}
        if minmax:
            a["min"], a["max"] = minmax
        self.accessors.append(a)
        return len(self.accessors) - 1


def f32(values):
    return struct.pack("<%df" % len(values), *values)


def main():
    mesh = Mesh()
    torso(mesh)
    head(mesh)
    leg(mesh, 1)
    leg(mesh, -1)
    arm(mesh, 1)
    arm(mesh, -1)

    b = Bin()
    flat = [round(c, 6) for p in mesh.positions for c in p]
    lo = [min(flat[i::3]) for i in range(3)]
    hi = [max(flat[i::3]) for i in range(3)]
    position = b.accessor(f32(flat), 5126, len(mesh.positions), "VEC3", 34962, (lo, hi))
    joints, weights = bytearray(), []
    for inf in mesh.influences:
        inf = sorted(inf, key=lambda x: -x[1])[:4]
        total = sum(w for _, w in inf)
        inf = [(j, w / total) for j, w in inf] + [(0, 0.0)] * (4 - len(inf))
        joints.extend(bytes(j for j, _ in inf))
        weights.extend(w for _, w in inf)
    joint_acc = b.accessor(bytes(joints), 5121, len(mesh.positions), "VEC4", 34962)
    weight_acc = b.accessor(f32(weights), 5126, len(mesh.positions), "VEC4", 34962)
    idx = [i for t in mesh.triangles for i in t]
    assert len(mesh.positions) < 65536
    index_acc = b.accessor(struct.pack("<%dH" % len(idx), *idx), 5123, len(idx), "SCALAR", 34963)
    ibm = []
    for name, _, _ in JOINTS:
        x, y, z = world_position(name)
        ibm.extend([1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -x, -y, -z, 1])
    ibm_acc = b.accessor(f32(ibm), 5126, len(JOINTS), "MAT4")

    times, channels = walk_channels()
    time_acc = b.accessor(f32(times), 5126, len(times), "SCALAR", None, ([times[0]], [times[-1]]))
    samplers, chans = [], []
    for (joint, path), values in sorted(channels.items()):
        kind = "VEC4" if path == "rotation" else "VEC3"
        out = b.accessor(f32([c for v in values for c in v]), 5126, len(values), kind)
        samplers.append({"input": time_acc, "output": out, "interpolation": "LINEAR"})
        chans.append({"sampler": len(samplers) - 1, "target": {"node": INDEX[joint], "path": path}})

    nodes = []
    for name, parent, t in JOINTS:
        node = {"name": name, "translation": list(t)}
        children = [i for i, (_, p, _) in enumerate(JOINTS) if p == name]
        if children:
            node["children"] = children
        nodes.append(node)
    nodes.append({"name": "walker_mesh", "mesh": 0, "skin": 0})
    doc = {
        "asset": {"version": "2.0", "generator": "trample scenes/meshes/make_walker.py"},
        "scene": 0,
        "scenes": [{"nodes": [INDEX["hips"], len(JOINTS)]}],
        "nodes": nodes,
        "meshes": [{"name": "walker", "primitives": [{
            "attributes": {"POSITION": position, "JOINTS_0": joint_acc, "WEIGHTS_0": weight_acc},
            "indices": index_acc, "mode": 4}]}],
        "skins": [{"name": "walker_skeleton", "joints": list(range(len(JOINTS))),
                   "inverseBindMatrices": ibm_acc, "skeleton": INDEX["hips"]}],
        "animations": [{"name": "walk", "samplers": samplers, "channels": chans}],
        "buffers": [{"byteLength": 0}],
        "bufferViews": b.views,
        "accessors": b.accessors,
    }
    while len(b.data) % 4:
        b.data.append(0)
    doc["buffers"][0]["byteLength"] = len(b.data)
    js = json.dumps(doc, separators=(",", ":"), sort_keys=True).encode()
    while len(js) % 4:
        js += b" "
    total = 12 + 8 + len(js) + 8 + len(b.data)
    glb = struct.pack("<4sII", b"glTF", 2, total)
    glb += struct.pack("<I4s", len(js), b"JSON") + js
    glb += struct.pack("<I4s", len(b.data), b"BIN\0") + bytes(b.data)
    with open(OUT, "wb") as f:
        f.write(glb)
    print("%s: %d vertices, %d triangles, %d joints, %d bytes" % (
        os.path.relpath(OUT), len(mesh.positions), len(mesh.triangles), len(JOINTS), len(glb)))


if __name__ == "__main__":
    main()
