#!/usr/bin/env python3
"""Writes the starting corpus of each fuzz target into fuzz/corpus/<target>/.

Run once from the repository root (`python3 fuzz/seeds/make_seeds.py`), then
fuzz and minimise (`cargo +nightly fuzz cmin <target>`): see CONTRIBUTING.md.
Seeds are small valid inputs of every kind the loaders accept, so the
fuzzer starts from deep inside each parser.
"""
import base64, json, os, struct, hashlib, shutil

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CORPUS = os.path.join(ROOT, "fuzz", "corpus")


def put(target, data):
    if isinstance(data, str):
        data = data.encode()
    d = os.path.join(CORPUS, target)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, hashlib.sha1(data).hexdigest()), "wb") as f:
        f.write(data)


# ---- scene -------------------------------------------------------------
SMALL = """[field]
patches = [2, 2]
cells_per_patch = 8
segments = {segments}
terrain = {terrain}
[lod]
geometry_m = {geo}
billboard_m = {bill}
[sim]
precision = {precision}
dt_s = {dt}
recovery_s = {recovery}
max_substeps = {substeps}
[camera]
path = {{ kind = "static", position = [0.0, 2.0, 3.0] }}
look_at = {{ kind = "point", at = [0.0, 0.0, 0.0] }}
"""
OBJECTS = [
    ('{ kind = "sphere", radius_m = 0.3, subdivisions = 2 }', '"rolling"',
     '{ kind = "line", from = [-1.0, 0.3, 0.0], to = [1.0, 0.3, 0.0], duration_s = 0.2 }'),
    ('{ kind = "box", half_extents_m = [0.3, 0.2, 0.4] }', '"face_motion"',
     '{ kind = "circle", center = [0.0, 0.2, 0.0], radius_m = 0.5, period_s = 1.0, phase_rad = 0.5 }'),
    ('{ kind = "capsule", radius_m = 0.2, length_m = 0.4 }', '"fixed"',
     '{ kind = "spline", points = [[-0.8, 0.2, 0.0], [0.0, 0.2, 0.5], [0.8, 0.2, 0.0]], speed_m_s = 3.0 }'),
    ('{ kind = "knot", size_m = 0.8 }', '"keyframes"',
     '{ kind = "keyframes", keys = [{ t_s = 0.0, position = [0.0, 0.3, 0.0], rotation_deg = [0.0, 0.0, 0.0] }, { t_s = 0.1, position = [0.2, 0.3, 0.1], rotation_deg = [90.0, 10.0, 0.0] }] }'),
    ('{ kind = "sphere", radius_m = 0.25 }', '"fixed"',
     '{ kind = "polyline", points = [[-0.8, 0.2, 0.0], [0.0, 0.2, 0.0], [0.0, 0.2, 0.8]], speed_m_s = 30.0 }'),
    ('{ kind = "mesh", path = "meshes/car.obj", anchor = "bottom" }', '"fixed"',
     '{ kind = "static", position = [0.0, 0.0, 0.0] }'),
]
variants = [
    dict(segments=4, terrain='{ kind = "flat" }', geo=100.0, bill=200.0, precision=3, dt=0.016666668, recovery='inf', substeps=16),
    dict(segments=1, terrain='{ kind = "noise", amplitude_m = 0.3, wavelength_m = 2.0, seed = 3 }', geo=0.5, bill=1.5, precision=7, dt=0.05, recovery=0.5, substeps=2),
    dict(segments=15, terrain='{ kind = "flat", height_m = 0.2 }', geo=1.0, bill=1.0, precision=1, dt=1.0, recovery=2.0, substeps=1024),
]
for i, (shape, orient, path) in enumerate(OBJECTS):
    v = variants[i % len(variants)]
    text = SMALL.format(**v)
    text += f'[[objects]]\nname = "o{i}"\nshape = {shape}\norientation = {orient}\npath = {path}\nscale = [1.0, 0.8, 1.2]\nrotation_deg = [10.0, 0.0, 5.0]\nstart_s = 0.01\n'
    put("scene", text)
put("scene", SMALL.format(**variants[0]) + "".join(
    f'[[objects]]\nname = "o{i}"\nshape = {s}\norientation = {o}\npath = {p}\n' for i, (s, o, p) in enumerate(OBJECTS[:3])))
put("scene", 'name = "h"\n[field]\npatches = [1, 1]\ncells_per_patch = 4\nterrain = { kind = "heightmap", path = "h.png", height_scale_m = 1.0 }\n[run]\nframes = 3\n')
for name in ["default.toml", "knot.toml", "car.toml"]:
    put("scene", open(os.path.join(ROOT, "scenes", name)).read())

# ---- OBJ ---------------------------------------------------------------
CUBE = ["v -1 -1 -1", "v 1 -1 -1", "v 1 1 -1", "v -1 1 -1", "v -1 -1 1", "v 1 -1 1", "v 1 1 1", "v -1 1 1"]
put("obj", "\n".join(CUBE + ["f 1 4 3 2", "f 5 6 7 8", "f 1 2 6 5", "f 2 3 7 6", "f 3 4 8 7", "f 4 1 5 8"]) + "\n")
put("obj", "\n".join(CUBE + ["vt 0 0", "vt 1 0", "vt 1 1", "vn 0 0 -1", "f 1/1/1 3/3/1 2/2/1", "f -8/1 -5/2 -6/3", "f 5//1 6//1 7//1 8//1 1//1"]) + "\n")
put("obj", "# comment\no a\ng b\nmtllib x.mtl\nusemtl m\ns off\nv 0 0 0\nv 1 0 0\nv 0 1 0 1.0\nv 0 0 1\nf 1 2 3\nl 1 2\np 4\nf 1 3 4\n")
put("obj", "v 0 0 0\nv 1e3 0 0\nv 0 1e-4 0\nv 1 1 1\nf 1 2 3 4\n")
with open(os.path.join(ROOT, "scenes", "meshes", "beetle.obj")) as f:
    lines = f.read().splitlines()
# The first 300 vertices and the faces that use only them: a real file's texture.
vs = [l for l in lines if l.startswith("v ")][:300]
fs = [l for l in lines if l.startswith("f ") and all(0 < int(w.split("/")[0]) <= 300 for w in l.split()[1:])][:300]
put("obj", "\n".join(vs + fs) + "\n")

# ---- glTF / GLB ---------------------------------------------------------
def tri_buffer(positions, indices):
    b = b"".join(struct.pack("<3f", *p) for p in positions)
    b += struct.pack(f"<{len(indices)}H", *indices)
    while len(b) % 4:
        b += b"\0"
    return b

def document(uri, positions, indices, nodes, mode=4, extra=None):
    pos_len = 12 * len(positions)
    buf = tri_buffer(positions, indices)
    lo = [min(p[k] for p in positions) for k in range(3)]
    hi = [max(p[k] for p in positions) for k in range(3)]
    d = {
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": len(buf)}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": pos_len},
            {"buffer": 0, "byteOffset": pos_len, "byteLength": 2 * len(indices)},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": len(positions), "type": "VEC3", "min": lo, "max": hi},
            {"bufferView": 1, "componentType": 5123, "count": len(indices), "type": "SCALAR"},
        ],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "mode": mode}]}],
        "nodes": nodes,
        "scenes": [{"nodes": list(range(len(nodes)))}] if nodes else [],
    }
    if uri:
        d["buffers"][0]["uri"] = uri
    if extra:
        d.update(extra)
    return d, buf

def glb(doc, buf):
    j = json.dumps(doc, separators=(",", ":")).encode()
    while len(j) % 4:
        j += b" "
    out = struct.pack("<II", len(j), 0x4E4F534A) + j
    if buf is not None:
        out += struct.pack("<II", len(buf), 0x004E4942) + buf
    return struct.pack("<III", 0x46546C67, 2, 12 + len(out)) + out

TET = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
TET_I = [0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3]
def data_uri(buf):
    return "data:application/octet-stream;base64," + base64.b64encode(buf).decode()

d, buf = document(None, TET, TET_I, [{"mesh": 0}])
d["buffers"][0]["uri"] = data_uri(buf)
put("gltf", json.dumps(d))
d, buf = document(None, TET, TET_I, [{"mesh": 0, "scale": [-1, 1, 1], "translation": [1, 2, 3]}, {"children": [0], "rotation": [0, 0.7071068, 0, 0.7071068]}])
d["scenes"] = [{"nodes": [1]}]
d["scene"] = 0
d["buffers"][0]["uri"] = data_uri(buf)
put("gltf", json.dumps(d))
d, buf = document(None, TET, [0, 1, 2, 3, 0, 1], [{"mesh": 0, "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]}], mode=5)
put("gltf", glb(d, buf))
d, buf = document(None, TET, [0, 1, 2, 3], [], mode=6)
put("gltf", glb(d, buf))
d, buf = document("tet.bin", TET, TET_I, [{"mesh": 0}])
put("gltf", json.dumps(d))

# ---- raw mesh (trample::fuzz_targets::mesh_from_bytes) --------------------
def raw(mode, verts, tris):
    out = bytes([mode, len(verts)])
    for v in verts:
        for c in v:
            out += struct.pack("<h", int(c * 1000)) if mode % 2 == 0 else struct.pack("<f", c)
    for t in tris:
        out += bytes(t)
    return out

CUBE_V = [(x, y, z) for z in (-1, 1) for y in (-1, 1) for x in (-1, 1)]
CUBE_T = [(0, 2, 3), (0, 3, 1), (4, 5, 7), (4, 7, 6), (0, 1, 5), (0, 5, 4), (2, 6, 7), (2, 7, 3), (0, 4, 6), (0, 6, 2), (1, 3, 7), (1, 7, 5)]
put("mesh", raw(0, CUBE_V, CUBE_T))
put("mesh", raw(1, CUBE_V, CUBE_T))
put("mesh", raw(0, TET, [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3), (1, 2, 3), (0, 0, 1)]))
put("mesh", raw(1, [(0, 0, 0), (1e30, 0, 0), (0, 1, 0), (float("nan"), 0, 0)], [(0, 1, 2), (0, 2, 3), (0, 1, 9)]))
put("mesh", raw(0, [(0, 0, 0), (0.001, 0, 0), (0, 0.001, 0), (30, 30, 30)], [(0, 1, 2), (0, 1, 3)]))
print("seeds written to", CORPUS)
