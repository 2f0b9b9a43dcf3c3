#!/usr/bin/env python3
"""Writes the seed inputs of fuzz/corpus/ (run once; the files are committed).
Each seed is a world descriptor (3 bytes) and a script of calls in the byte
format fuzz_api.cpp reads: mesh creates of preset and random shapes, body
creates near the world's anchor, detects, poses, velocities, steps, destroys
and reads; seeds 40 to 47 add batch calls. Deterministic (seeded)."""
import os, random

OP = dict(mesh=0, mesh_destroy=2, body=3, body_destroy=6, pose=7, velocity=9, step=10, detect=11, read=13,
          batch=16)

def quaternion(r):
    k = r.random()
    if k < 0.45:
        return [r.randrange(0, 100)]                                   # exact rotation
    if k < 0.9:
        return [r.randrange(100, 200)] + [r.randrange(256) for _ in range(6)]  # random rotation
    return [r.randrange(200, 256)]                                     # odd: non-unit, NaN, ...

def seed(k):
    r = random.Random(k)
    anchor = k % 6
    unit = (k // 6) % 4
    a = (k & 3) | (r.choice([0, 0, 0, 1, 3, 4]) << 2)        # threads, reflect, time step
    b = r.choice([0, 0, 1, 3, 4, 5, 6, 7]) | (anchor << 4)    # cell limits, anchor
    c = unit | (r.randrange(1, 16) << 2)                      # unit, non-empty bounds
    out = [a, b, c]
    def op(name, *payload):
        out.append(OP[name]); out.extend(payload)
    nmesh = r.randrange(1, 4)
    for _ in range(nmesh):
        if r.random() < 0.7:
            op('mesh', r.randrange(0, 120), 200 + r.randrange(0, 50))          # preset, no corruption
        else:
            nv, nt = r.randrange(3, 9), r.randrange(1, 11)
            op('mesh', 130, nv, nt, *[r.randrange(0, 240) for _ in range(3 * nv)],
               *[r.randrange(0, 250) for _ in range(3 * nt)], 200)
    for _ in range(r.randrange(3, 12)):
        mesh_pick = r.randrange(0, 200)
        pos = [r.randrange(0, 256) if r.random() < 0.1 else r.randrange(0, 200) for _ in range(3)]
        quat = quaternion(r)
        vel = [r.randrange(0, 256) for _ in range(3)]
        scale = r.randrange(0, 256) if r.random() < 0.2 else r.randrange(0, 128)
        op('body', mesh_pick, *pos, *quat, *vel, scale, *[r.randrange(256) for _ in range(4)], 3 + r.randrange(0, 200))
    for _ in range(r.randrange(2, 10)):
        what = r.choice(['detect', 'pose', 'velocity', 'step', 'read', 'body_destroy', 'mesh_destroy', 'detect'])
        if what == 'detect' or what == 'step':
            op(what)
        elif what == 'pose':
            op('pose', r.randrange(0, 220), *[r.randrange(0, 200) for _ in range(3)],
               *quaternion(r), r.randrange(4))
        elif what == 'velocity':
            op('velocity', r.randrange(0, 220), *[r.randrange(256) for _ in range(3)], 1 + r.randrange(15))
        elif what == 'read':
            op('read', *[r.randrange(256) for _ in range(6)])
        else:
            op(what, r.randrange(0, 256), r.randrange(256))
    op('detect')
    return bytes(out)

def batch_seed(k):
    """seed(k) with batch calls before its last detect: each a call, flags
    (by index when flags % 4 == 0; clean values), good strides, then bytes
    below 200 for the ids and values (grid coordinates, valid rotations);
    where they land depends on the bodies the seed made, which the fuzzer
    sorts out."""
    r = random.Random(1000 + k)
    out = bytearray(seed(k)[:-1])
    for _ in range(r.randrange(2, 6)):
        call = r.randrange(8)
        flags = (r.choice([0, 1, 2, 3]) | r.choice([1, 2, 3]) << 2 | r.randrange(2) << 4) & 0x1f
        arrays = r.choice([0, 0, 0, 5, 6])
        strides = [r.choice([0, 0, 5, 6, 7, 8]) for _ in range(2)]  # table positions of good strides
        out += bytes([OP['batch'], call, flags, 0, arrays] + strides)
        out += bytes(r.randrange(200) for _ in range(r.randrange(20, 80)))
        if r.random() < 0.5:
            out.append(OP['detect'])
    out.append(OP['detect'])
    return bytes(out)

here = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'corpus')
os.makedirs(here, exist_ok=True)
for k in range(40):
    with open(os.path.join(here, 'seed-%02d' % k), 'wb') as f:
        f.write(seed(k))
for k in range(40, 48):
    with open(os.path.join(here, 'seed-%02d' % k), 'wb') as f:
        f.write(batch_seed(k))
