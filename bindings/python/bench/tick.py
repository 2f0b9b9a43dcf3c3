#!/usr/bin/env python3
"""A physics engine's tick from Python, as bench_hgcd --mode engine-batch does it
in C: scene tetra on one shared unit tetrahedron in a world reflecting at the
scene's cube; each tick the caller moves its centres (hgcd.scene.move) and
turns each body by its own fixed rotation (numpy, the same arithmetic as
bench_hgcd.c, so the pairs are the same bits) -- not timed -- then, timed:
the poses handed over in one set_poses call, detect(), and pairs() read into
a new (N, 2) array. Prints one JSON line: medians of set_poses_ms, detect_ms,
pairs_ms and their sum per tick wall_ms, and pairs_fnv of the last tick
(FNV-1a over the pair indices, as bench_hgcd prints it).

With --against-c C_TICK_SO (bench/c_tick.c, built by compare.sh) a second
world, made and ticked by C, gets the same poses every tick, its tick (set
poses, detect, pairs read in place) timed in C; the two alternate which goes
first. Adds the C tick's medians (c_wall_ms, and c_cpu_ms: CPU time of the
process, all threads, which a busy machine inflates less than wall-clock time;
cpu_ms is the Python tick's), the median and quartiles of the per-tick
ratios Python / C of both, and whether every tick gave the same pairs.

    tick.py [--n N] [--seed S] [--threads K] [--ticks T] [--turn A] [--against-c SO]
"""
import argparse
import json
import time

import numpy as np

import hgcd


def square_root(x):
    """bench_hgcd.c's square_root: Newton from above until the iterates stop decreasing."""
    y = np.maximum(x, 1.0)
    while True:
        nxt = 0.5 * (y + x / y)
        down = nxt < y
        if not down.any():
            return np.where(x > 0, y, 0.0)
        y = np.where(down, nxt, y)


def make_turns(turn, velocities):
    h = 0.5 * turn
    v = velocities
    speed = square_root((v[:, 0] * v[:, 0] + v[:, 1] * v[:, 1]) + v[:, 2] * v[:, 2])
    axis = np.tile([0.0, 0.0, 1.0], (len(v), 1))
    moving = speed > 0
    axis[moving] = v[moving] / speed[moving, None]
    norm = square_root(np.array([1 + h * h]))[0]
    turns = np.empty((len(v), 4))
    turns[:, :3] = h * axis / norm
    turns[:, 3] = 1 / norm
    return turns


def turn_bodies(q, r):
    """q = q * r, normalised by one Newton step, in place (bench_hgcd.c's turn_bodies)."""
    q0, q1, q2, q3 = q.T
    r0, r1, r2, r3 = r.T
    x = q3 * r0 + q0 * r3 + q1 * r2 - q2 * r1
    y = q3 * r1 - q0 * r2 + q1 * r3 + q2 * r0
    z = q3 * r2 + q0 * r1 - q1 * r0 + q2 * r3
    w = q3 * r3 - q0 * r0 - q1 * r1 - q2 * r2
    scale = 0.5 * (3 - (((x * x + y * y) + z * z) + w * w))
    q[:, 0], q[:, 1], q[:, 2], q[:, 3] = x * scale, y * scale, z * scale, w * scale


def fnv(pairs):
    h = 14695981039346656037
    for byte in np.ascontiguousarray(pairs, dtype="<u4").tobytes():
        h = ((h ^ byte) * 1099511628211) & 0xFFFFFFFFFFFFFFFF
    return f"{h:016x}"


C_DECLS = """
typedef struct hgcd_world hgcd_world;
hgcd_world *c_world_create(uint64_t n, double side, unsigned threads, const double *centers,
                           const double *orientations, const double *velocities, const double *scales);
int32_t c_tick(hgcd_world *w, uint64_t n, const double *centers, const double *orientations,
               double *seconds, double *cpu_seconds, uint64_t *count, uint64_t *fnv);
void c_world_destroy(hgcd_world *w);
"""


class CWorld:
    """The same tick in C (c_tick.c, built by compare.sh), in this process."""

    def __init__(self, path, s, threads):
        import cffi

        self.ffi = cffi.FFI()
        self.ffi.cdef(C_DECLS)
        self.lib = self.ffi.dlopen(path)
        d = lambda a: self.ffi.cast("double *", a.ctypes.data)  # noqa: E731
        self.d = d
        self.w = self.lib.c_world_create(len(s.centers), s.side, threads, d(s.centers), d(s.orientations),
                                         d(s.velocities), d(s.scales))
        assert self.w != self.ffi.NULL
        self.out = [self.ffi.new(t) for t in ("double *", "double *", "uint64_t *", "uint64_t *")]

    def tick(self, centers, orientations):
        assert self.lib.c_tick(self.w, len(centers), self.d(centers), self.d(orientations), *self.out) == 0
        return self.out[0][0], self.out[1][0], self.out[2][0], f"{self.out[3][0]:016x}"

    def close(self):
        self.lib.c_world_destroy(self.w)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--n", type=int, default=200000)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--threads", type=int, default=1)
    p.add_argument("--ticks", type=int, default=15)
    p.add_argument("--turn", type=float, default=0.01)
    p.add_argument("--against-c", metavar="C_TICK_SO",
                   help="also tick a C-driven world in this process, alternating tick by tick")
    a = p.parse_args()

    s = hgcd.scene.tetra(a.n, a.seed)
    turns = make_turns(a.turn, s.velocities)
    c_world = CWorld(a.against_c, s, a.threads) if a.against_c else None
    centers, velocities, orientations = s.centers.copy(), s.velocities.copy(), s.orientations.copy()
    py_times, c_times, same = [], [], True
    with hgcd.World(threads=a.threads, thread_policy=hgcd.ThreadPolicy.FIXED,
                    bounds=((0, 0, 0), (s.side,) * 3)) as world:
        mesh = world.create_mesh(*hgcd.scene.unit_mesh())
        world.create_bodies(mesh, centers, orientations, velocities, s.scales, np.arange(a.n, dtype=np.uint64))
        world.detect()
        for tick in range(a.ticks):
            hgcd.scene.move(centers, velocities, s.side)
            if a.turn > 0:
                turn_bodies(orientations, turns)
            if c_world and tick % 2 == 1:
                c_times.append(c_world.tick(centers, orientations))
            c0, t0 = time.process_time(), time.perf_counter()
            world.set_poses(centers, orientations)
            t1 = time.perf_counter()
            world.detect()
            t2 = time.perf_counter()
            pairs = world.pairs()
            t3, c3 = time.perf_counter(), time.process_time()
            py_times.append((t1 - t0, t2 - t1, t3 - t2, t3 - t0, c3 - c0))
            if c_world and tick % 2 == 0:
                c_times.append(c_world.tick(centers, orientations))
            if c_world:
                same = same and c_times[-1][2] == len(pairs) and c_times[-1][3] == fnv(pairs)
        st = world.stats()
    med = np.median(np.array(py_times), axis=0) * 1e3
    result = {"lib": "hgcd-python", "scene": "tetra", "n": a.n, "seed": a.seed,
              "threads": st.thread_count, "ticks": a.ticks, "turn": a.turn,
              "set_poses_ms": round(med[0], 3), "detect_ms": round(med[1], 3),
              "pairs_ms": round(med[2], 3), "wall_ms": round(med[3], 3),
              "colliding_pairs": len(pairs), "pairs_fnv": fnv(pairs)}
    if c_world:
        c_world.close()
        c = np.array([t[:2] for t in c_times])
        py = np.array(py_times)[:, 3:]
        wall, cpu = py[:, 0] / c[:, 0], py[:, 1] / c[:, 1]
        result.update({"cpu_ms": round(float(np.median(py[:, 1])) * 1e3, 3),
                       "c_wall_ms": round(float(np.median(c[:, 0])) * 1e3, 3),
                       "c_cpu_ms": round(float(np.median(c[:, 1])) * 1e3, 3),
                       "wall_ratio_median": round(float(np.median(wall)), 4),
                       "wall_ratio_quartiles": [round(float(q), 4) for q in np.percentile(wall, [25, 75])],
                       "cpu_ratio_median": round(float(np.median(cpu)), 4),
                       "cpu_ratio_quartiles": [round(float(q), 4) for q in np.percentile(cpu, [25, 75])],
                       "same_pairs_every_tick": bool(same)})
    print(json.dumps(result))


if __name__ == "__main__":
    main()
