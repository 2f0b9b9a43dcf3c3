#!/usr/bin/env python3
"""Chart and Markdown table of a benchmark run (bench/results/<machine>/<scene>.jsonl).

    python3 bench/plot.py bench/results/<machine>/tetra.jsonl [--out FILE.svg]

Writes <scene>.svg next to the input file (--out to choose another path):
time per tick against n on log-log axes, for hgcd's whole tick (tick_ms) and
its broad phase (broad_ms) at each thread count measured, and each peer's
broad phase (broad_ms). The SVG is written by hand, so nothing beyond python3
is needed. Then prints a Markdown table, also saved as <scene>.md.

When a file holds several runs of the same (lib, threads, n, mode, mesh per
body), the last line wins. Lines with "skipped" or "error" are listed in the
table, not plotted. bench_hgcd's engine modes ("mode" other than "step": the
caller moves the bodies and hands the poses over, then detects) get a table of
their own, beside step mode's tick at the same n and thread count; they are
not plotted.
"""
import argparse
import json
import math
import os
import platform
import sys
from xml.sax.saxutils import escape

LIB_ORDER = {"hgcd": 0, "fcl": 1, "bullet": 2, "ode": 3}
PEER_NAMES = {"fcl": "FCL DynamicAABBTree", "bullet": "Bullet btDbvtBroadphase", "ode": "ODE hash space"}
MODE_ORDER = {"step": 0, "engine-batch": 1, "engine-single": 2}
PALETTE = ["#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf"]


def load(path):
    rows = {}
    with open(path) as f:
        for lineno, line in enumerate(f, 1):
            line = line.strip()
            if not line:
                continue
            try:
                r = json.loads(line)
            except ValueError as e:
                print(f"plot.py: {path}:{lineno}: not JSON ({e}), ignored", file=sys.stderr)
                continue
            if "lib" not in r or "n" not in r:
                continue
            rows[(r["lib"], int(r.get("threads", 1) or 1), int(r["n"]), mode_of(r), bool(r.get("mesh_per_body")))] = r
    return sorted(rows.values(), key=lambda r: (int(r["n"]), LIB_ORDER.get(r["lib"], 9), r["lib"],
                                                 int(r.get("threads", 1) or 1), MODE_ORDER.get(mode_of(r), 9),
                                                 bool(r.get("mesh_per_body"))))


def mode_of(r):
    """bench_hgcd's mode; lines without one (peers, earlier runs) are step mode's."""
    return r.get("mode", "step")


def is_engine(r):
    return mode_of(r) != "step"


def usable(r, key):
    return "skipped" not in r and "error" not in r and isinstance(r.get(key), (int, float)) and r[key] > 0


def series_of(rows):
    """[(label, colour, dashed, [(n, ms), ...])]"""
    out = []
    colour = iter(PALETTE)
    threads = sorted({int(r.get("threads", 1)) for r in rows if r["lib"] == "hgcd"})
    for t in threads:
        c = next(colour)
        sel = [r for r in rows if r["lib"] == "hgcd" and int(r.get("threads", 1)) == t]
        unit = "thread" if t == 1 else "threads"
        out.append((f"hgcd whole tick, {t} {unit}", c, False,
                    [(int(r["n"]), r["tick_ms"]) for r in sel if usable(r, "tick_ms")]))
        out.append((f"hgcd broad (boxes), {t} {unit}", c, True,
                    [(int(r["n"]), r["broad_ms"]) for r in sel if usable(r, "broad_ms")]))
    # (hgcd-long, a longer run at one n, is in the table only)
    peers = sorted({r["lib"] for r in rows if not r["lib"].startswith("hgcd")}, key=lambda l: (LIB_ORDER.get(l, 9), l))
    for lib in peers:
        sel = [r for r in rows if r["lib"] == lib]
        out.append((f"{PEER_NAMES.get(lib, lib)}: broad (boxes)", next(colour, "#444444"), True,
                    [(int(r["n"]), r["broad_ms"]) for r in sel if usable(r, "broad_ms")]))
    return [s for s in out if s[3]]


def machine_of(rows):
    for r in rows:
        if r.get("nproc"):
            cpu = r.get("cpu") or ""
            name = f"{r['machine']}: " if r.get("machine") else ""
            return f"{name}{r['nproc']} cores" + (f", {cpu}" if cpu else "")
    cpu = ""
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    return f"{os.cpu_count()} cores" + (f", {cpu or platform.machine()}")


def commits_of(rows):
    seen = []
    for r in rows:
        c = r.get("commit", "unknown")
        if c not in seen:
            seen.append(c)
    return ", ".join(seen) or "unknown"


def nice_log_ticks(lo, hi):
    """Tick values 1, 2, 5 x 10^k inside [lo, hi] (fewer when the range is wide)."""
    ticks = []
    steps = (1, 2, 5) if math.log10(hi / lo) <= 3 else (1,)
    for k in range(math.floor(math.log10(lo)) - 1, math.ceil(math.log10(hi)) + 1):
        for m in steps:
            v = m * 10.0 ** k
            if lo <= v <= hi:
                ticks.append(v)
    return ticks


def fmt_n(v):
    if v >= 1e6 and v % 1e5 == 0:
        return f"{v / 1e6:g}M"
    if v >= 1e3 and v % 1e3 == 0:
        return f"{v / 1e3:g}k"
    return f"{v:g}"


def fmt_ms(v):
    if v >= 1000:
        return f"{v / 1000:g} s"
    return f"{v:g} ms"


def write_svg(rows, series, path):
    W, H = 1000, 600
    left, right, top, bottom = 80, 330, 70, 70
    pw, ph = W - left - right, H - top - bottom
    ns = sorted({p[0] for s in series for p in s[3]})
    ys = [p[1] for s in series for p in s[3]]
    if not ns or not ys:
        xlo, xhi, ylo, yhi = 1e5, 1e6, 1.0, 1e3
    else:
        xlo, xhi = min(ns) / 1.25, max(ns) * 1.25
        ylo, yhi = min(ys) / 1.6, max(ys) * 1.6
    lxlo, lxhi, lylo, lyhi = math.log10(xlo), math.log10(xhi), math.log10(ylo), math.log10(yhi)

    def X(n):
        return left + pw * (math.log10(n) - lxlo) / (lxhi - lxlo)

    def Y(ms):
        return top + ph * (1.0 - (math.log10(ms) - lylo) / (lyhi - lylo))

    title = f"Scene tetra: time per tick vs n ({machine_of(rows)}; commit {commits_of(rows)})"
    o = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" viewBox="0 0 {W} {H}" '
         f'font-family="sans-serif" font-size="12">',
         f'<rect width="{W}" height="{H}" fill="white"/>',
         f'<text x="{W / 2}" y="28" text-anchor="middle" font-size="15" font-weight="bold">{escape(title)}</text>',
         f'<text x="{W / 2}" y="48" text-anchor="middle" fill="#555">median over the measured ticks; '
         f'log-log; peers (1 thread): broad phase only, on the bodies\' axis-aligned boxes</text>']
    # Grid and axes.
    xt = sorted(set(ns)) if ns else nice_log_ticks(xlo, xhi)
    for v in xt:
        x = X(v)
        o.append(f'<line x1="{x:.1f}" y1="{top}" x2="{x:.1f}" y2="{top + ph}" stroke="#e4e4e4"/>')
        o.append(f'<text x="{x:.1f}" y="{top + ph + 18}" text-anchor="middle">{fmt_n(v)}</text>')
    for v in nice_log_ticks(ylo, yhi):
        y = Y(v)
        o.append(f'<line x1="{left}" y1="{y:.1f}" x2="{left + pw}" y2="{y:.1f}" stroke="#e4e4e4"/>')
        o.append(f'<text x="{left - 6}" y="{y + 4:.1f}" text-anchor="end">{fmt_ms(v)}</text>')
    o.append(f'<rect x="{left}" y="{top}" width="{pw}" height="{ph}" fill="none" stroke="#333"/>')
    o.append(f'<text x="{left + pw / 2}" y="{H - 25}" text-anchor="middle" font-size="13">'
             f'n (tetrahedra in the 200^3 cube)</text>')
    o.append(f'<text transform="translate(22,{top + ph / 2}) rotate(-90)" text-anchor="middle" font-size="13">'
             f'time per tick (log scale)</text>')
    # Series and legend.
    ly = top + 10
    for label, colour, dashed, pts in series:
        pts = sorted(pts)
        dash = ' stroke-dasharray="7,4"' if dashed else ""
        if len(pts) > 1:
            d = " ".join(f"{X(n):.1f},{Y(ms):.1f}" for n, ms in pts)
            o.append(f'<polyline points="{d}" fill="none" stroke="{colour}" stroke-width="2"{dash}/>')
        for n, ms in pts:
            o.append(f'<circle cx="{X(n):.1f}" cy="{Y(ms):.1f}" r="3.5" fill="{colour}">'
                     f'<title>{escape(label)}: n = {n}, {ms:.1f} ms</title></circle>')
        lx = left + pw + 20
        o.append(f'<line x1="{lx}" y1="{ly}" x2="{lx + 30}" y2="{ly}" stroke="{colour}" stroke-width="2"{dash}/>')
        o.append(f'<circle cx="{lx + 15}" cy="{ly}" r="3.5" fill="{colour}"/>')
        o.append(f'<text x="{lx + 38}" y="{ly + 4}">{escape(label)}</text>')
        ly += 22
    skipped = [r for r in rows if "skipped" in r or "error" in r]
    for r in skipped:
        what = "skipped" if "skipped" in r else "failed"
        o.append(f'<text x="{left + pw + 20}" y="{ly + 4}" fill="#777" font-size="11">'
                 f'{escape(r["lib"])} at n = {fmt_n(int(r["n"]))}: {what}</text>')
        ly += 16
    o.append("</svg>")
    with open(path, "w") as f:
        f.write("\n".join(o) + "\n")


def cell(v, digits=1):
    return f"{v:.{digits}f}" if isinstance(v, (int, float)) else "–"


def engine_markdown(rows):
    """The engine modes' table: hgcd's part of a tick (poses handed over + detect) beside step mode's tick."""
    engine = [r for r in rows if is_engine(r)]
    if not engine:
        return []
    step = {(r["lib"], int(r["n"]), int(r.get("threads", 1))): r for r in rows
            if not is_engine(r) and "error" not in r and "skipped" not in r and not r.get("mesh_per_body")}
    out = ["", "Engine modes: the caller moves and turns the bodies (caller ms, not hgcd's), hands the poses over "
           "(set poses ms: one `hgcd_world_set_poses`, or one `hgcd_body_set_pose` per body) and calls "
           "`hgcd_world_detect` (detect ms); tick = set poses + detect. Step tick: `hgcd_world_step`'s wall-clock "
           "time in the step-mode line of the same n and threads (whose bodies do not turn).",
           "",
           "| n | threads | mode | meshes | set poses ms | detect ms | tick ms | step tick ms | caller ms | pairs | ticks |",
           "|---:|---:|---|---|---:|---:|---:|---:|---:|---:|---:|"]
    for r in engine:
        n, t = int(r["n"]), int(r.get("threads", 1))
        meshes = "one per body" if r.get("mesh_per_body") else "shared"
        if "error" in r or "skipped" in r:
            out.append(f"| {n} | {t} | {mode_of(r)} | {meshes} | – | – | – | – | – | failed: "
                       f"{r.get('error') or r.get('skipped')} | 0 |")
            continue
        sp, det = r.get("set_poses_ms"), r.get("detect_ms")
        tick = sp + det if isinstance(sp, (int, float)) and isinstance(det, (int, float)) else None
        s = step.get((r["lib"], n, t), {})
        turn = r.get("turn")
        pairs = f"{r.get('colliding_pairs', '?')}" + (" (no turning)" if turn == 0 else "")
        out.append(f"| {n} | {t} | {mode_of(r)} | {meshes} | {cell(sp)} | {cell(det)} | {cell(tick)} | "
                   f"{cell(s.get('wall_ms'))} | {cell(r.get('caller_ms'))} | {pairs} | {r.get('ticks', '?')} |")
    return out


def markdown(rows):
    engine_lines = engine_markdown(rows)
    rows = [r for r in rows if not is_engine(r)]
    out = ["| n | lib | threads | broad ms | narrow ms | tick ms | mean tick ms | pairs | ticks |",
           "|---:|---|---:|---:|---:|---:|---:|---|---:|"]
    for r in rows:
        lib, n, t = r["lib"], int(r["n"]), r.get("threads", 1)
        if "skipped" in r or "error" in r:
            why = r.get("skipped") or r.get("error")
            out.append(f"| {n} | {lib} | {t} | – | – | – | – | {'skipped' if 'skipped' in r else 'failed'}: "
                       f"{why} | 0 |")
            continue
        if lib.startswith("hgcd"):
            pairs = f"{r.get('colliding_pairs', '?')} colliding / {r.get('candidate_pairs', '?')} box candidates"
            if r.get("reference_ok") is False:
                pairs += " (initial detect ≠ docs/scenes.md!)"
            narrow, tick, mean = cell(r.get("narrow_ms")), cell(r.get("tick_ms")), cell(r.get("tick_mean_ms"))
        else:
            ok = r.get("pairs_ok")
            pairs = f"{r.get('candidate_pairs', '?')} box overlaps" + (" (≠ sweep!)" if ok is False else "")
            narrow, tick, mean = "–", "–", "–"
        ticks = r.get("ticks", "?")
        if r.get("ticks_requested") not in (None, ticks):
            ticks = f"{ticks} of {r['ticks_requested']}"
        out.append(f"| {n} | {lib} | {t} | {cell(r.get('broad_ms'))} | {narrow} | {tick} | {mean} | {pairs} | {ticks} |")
    out.append("")
    out.append(f"Scene `tetra` (docs/scenes.md, seed {rows[0].get('seed', 1) if rows else 1}), "
               f"{machine_of(rows)}, commit {commits_of(rows)}; medians over the ticks, and hgcd's mean tick "
               "(with the ticks that renumber storage; hgcd-long: a longer run, whose mean counts renumberings at "
               "their real rate). "
               "hgcd: broad phase on each body's axis-aligned box of its world vertices, exact narrow phase, tick = motion + grid update + broad + "
               "narrow (the motion runs inside the grid update's pass over the bodies). Peers: broad phase only (update + pair search) on each body's axis-aligned box; their pair "
               "counts are checked against a sort-and-sweep of the same boxes.")
    out.extend(engine_lines)
    return "\n".join(out)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("jsonl")
    ap.add_argument("--out", help="SVG path (default: <scene>.svg next to the input)")
    a = ap.parse_args()
    rows = load(a.jsonl)
    if not rows:
        print(f"plot.py: no measurements in {a.jsonl}", file=sys.stderr)
        return 1
    out = a.out or os.path.splitext(a.jsonl)[0] + ".svg"
    step_rows = [r for r in rows if not is_engine(r)]
    write_svg(step_rows, series_of(step_rows), out)
    table = markdown(rows)
    md = os.path.splitext(a.jsonl)[0] + ".md"
    with open(md, "w") as f:
        f.write(table + "\n")
    print(table)
    print(f"\nchart: {out}\ntable: {md}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
