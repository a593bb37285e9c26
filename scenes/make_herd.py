#!/usr/bin/env python3
"""Writes scenes/herd.toml and scenes/herd_small.toml: 128 mixed objects
(balls, boxes, knots, the beetle car, the cow) each circling somewhere on a
large field (issue 16); and scenes/herd_parked.toml: the same 128 objects
on herd.toml's field, parked where their circles start (objects at rest,
`sim.reuse_at_rest`); and scenes/herd_stopgo.toml: herd.toml with each
object going round its circle in legs of 1.5-4 s, each stopped, at half,
full or one and a half times its speed (keyframes, 20 s; then it stays
where it is): far bodies that change speed (issue 16's far turns). Run
from the repository root:

    python3 scenes/make_herd.py

The positions, sizes and speeds come from a fixed seed, so the files are
reproducible; edit the constants below and run it again rather than editing
the TOML by hand.
"""

import math
import random

KINDS = ["ball"] * 32 + ["box"] * 32 + ["knot"] * 24 + ["car"] * 20 + ["cow"] * 20
assert len(KINDS) == 128


def stop_go_keys(cx, y, cz, r, speed, phase, seed, total_s=20.0, spacing_s=0.5):
    """Keyframes round the circle (centre + r (cos t, 0, -sin t), as a
    circle path) in legs of 1.5-4 s, each at 0, 0.5, 1 or 1.5 times
    `speed` (not the last leg's), a key at least every spacing_s while moving. Its own seeded
    generator, so the other scenes' numbers are untouched."""
    rng = random.Random(seed)
    keys = []
    t, theta, factor = 0.0, phase, None

    def key(t, theta):
        x, z = cx + r * math.cos(theta), cz - r * math.sin(theta)
        keys.append(f"    {{ t_s = {t:.3f}, position = [{x:.3f}, {y}, {z:.3f}] }},")

    key(t, theta)
    while t < total_s:
        leg = rng.uniform(1.5, 4.0)
        factor = rng.choice([f for f in (0.0, 0.5, 1.0, 1.5) if f != factor])
        pieces = 1 if factor == 0.0 else math.ceil(leg / spacing_s)
        omega = factor * speed / r
        for _ in range(pieces):
            t += leg / pieces
            theta += omega * leg / pieces
            key(t, theta)
    return "[\n" + "\n".join(keys) + "\n]"


def objects(extent_m, seed, radius_range, parked=False, stop_go=False):
    """One [[objects]] block per object, on a jittered 16 x 8 grid over a
    square field of side extent_m centred on the origin; parked: standing
    still where its circle starts; stop_go: round its circle at changing
    speeds (stop_go_keys)."""
    rng = random.Random(seed)
    kinds = KINDS[:]
    rng.shuffle(kinds)
    cols, rows = 16, 8
    out = []
    for i, kind in enumerate(kinds):
        cx = (-0.5 + (i % cols + 0.5) / cols) * extent_m * 0.9
        cz = (-0.5 + (i // cols + 0.5) / rows) * extent_m * 0.9
        cx += rng.uniform(-0.15, 0.15) * extent_m / cols
        cz += rng.uniform(-0.15, 0.15) * extent_m / rows
        r = rng.uniform(*radius_range)
        speed = rng.uniform(1.5, 4.0)
        period = 2.0 * math.pi * r / speed
        phase = rng.uniform(0.0, 2.0 * math.pi)
        name = f"{kind}{i}"
        if kind == "ball":
            rad = round(rng.uniform(0.4, 1.0), 2)
            shape = f'{{ kind = "sphere", radius_m = {rad} }}'
            extra = 'orientation = "rolling"'
            y = rad
        elif kind == "box":
            h = [round(rng.uniform(0.3, 0.8), 2) for _ in range(3)]
            shape = f'{{ kind = "box", half_extents_m = [{h[0]}, {h[1]}, {h[2]}] }}'
            extra = 'orientation = "face_motion"'
            y = h[1]
        elif kind == "knot":
            size = round(rng.uniform(1.2, 2.4), 2)
            shape = f'{{ kind = "knot", size_m = {size} }}'
            extra = 'rotation_deg = [0.0, 90.0, 0.0]\norientation = "face_motion"'
            y = round(0.7 * size / 2.4, 3)
        elif kind == "car":
            shape = '{ kind = "mesh", path = "meshes/beetle.obj", anchor = "bottom" }'
            extra = 'scale = 4.5\norientation = "face_motion"'
            y = 0.0
        else:
            shape = '{ kind = "mesh", path = "meshes/spot.obj", anchor = "bottom" }'
            extra = 'scale = 1.4\norientation = "face_motion"'
            y = 0.0
        if stop_go:
            # The circle as herd.toml writes it (rounded), at its speed.
            rc, pc = round(r, 2), round(period, 2)
            keys = stop_go_keys(round(cx, 2), y, round(cz, 2), rc, 2.0 * math.pi * rc / pc,
                                round(phase, 3), seed * 1000 + i)
            path = f'{{ kind = "keyframes", keys = {keys} }}'
        elif parked:
            extra = "\n".join(l for l in extra.split("\n") if not l.startswith("orientation"))
            x, z = cx + r * math.cos(phase), cz + r * math.sin(phase)
            path = f'{{ kind = "static", position = [{x:.2f}, {y}, {z:.2f}] }}'
        else:
            path = (
                f'{{ kind = "circle", center = [{cx:.2f}, {y}, {cz:.2f}], '
                f"radius_m = {r:.2f}, period_s = {period:.2f}, phase_rad = {phase:.3f} }}"
            )
        extra = f"{extra}\n" if extra else ""
        out.append(f'[[objects]]\nname = "{name}"\nshape = {shape}\n{extra}path = {path}\n')
    return "\n".join(out)


def scene(name, description, patches, extent_m, radius_range, comment, limit=8.0, parked=False,
          stop_go=False):
    return f"""# {comment}
# Written by scenes/make_herd.py (seeded): edit that and run it again.
name = "{name}"
description = "{description}"

[field]
patches = [{patches}, {patches}]

[sim]
precision = 7
memory_limit_gib = {limit}

[camera]
path = {{ kind = "static", position = [0.0, 8.0, -6.0] }}
look_at = {{ kind = "point", at = [0.0, 0.0, 10.0] }}

{objects(extent_m, 128, radius_range, parked, stop_go)}"""


# The default field's patches are 32 x 32 cells of 0.1 m: 3.2 m.
with open("scenes/herd.toml", "w") as f:
    f.write(
        scene(
            "herd",
            "128 objects (balls, boxes, knots, cars, cows) circling over 16.8 M blades",
            128,
            128 * 3.2,
            (3.0, 8.0),
            "128 mixed objects, each circling somewhere on a 128 x 128-patch field\n"
            "# (16,777,216 blades, 409.6 m square), precision 7, camera at the centre:\n"
            "# issue 16's scene. Memory: the estimate is 10.1 GiB (the worst case,\n"
            "# every blade bent; a run peaks at about a third), so the limit is\n"
            "# raised to 12 GiB.",
            12.0,
        )
    )
with open("scenes/herd_small.toml", "w") as f:
    f.write(
        scene(
            "herd_small",
            "herd.toml's 128 objects on a 32 x 32-patch field (1 M blades), for tests",
            32,
            32 * 3.2,
            (1.0, 2.5),
            "herd.toml on a smaller field (32 x 32 patches, 1,048,576 blades,\n"
            "# 102.4 m square) with tighter circles: for CI and tests.",
        )
    )
with open("scenes/herd_parked.toml", "w") as f:
    f.write(
        scene(
            "herd_parked",
            "herd.toml's 128 objects parked where their circles start, over 16.8 M blades",
            128,
            128 * 3.2,
            (3.0, 8.0),
            "herd.toml's 128 objects standing still where their circles start, on its\n"
            "# 16,777,216-blade field: what objects at rest cost (sim.reuse_at_rest).",
            12.0,
            parked=True,
        )
    )
with open("scenes/herd_stopgo.toml", "w") as f:
    f.write(
        scene(
            "herd_stopgo",
            "herd.toml's 128 objects going round their circles in legs: stopped, slow, fast",
            128,
            128 * 3.2,
            (3.0, 8.0),
            "herd.toml's 128 objects going round their circles in legs of 1.5-4 s,\n"
            "# each stopped or at 0.5, 1 or 1.5 times the object's speed (keyframes\n"
            "# for 20 s, then each stays where it is), on its 16,777,216-blade field:\n"
            "# far bodies that change speed (issue 16's far turns, `--far-every`).",
            12.0,
            stop_go=True,
        )
    )
