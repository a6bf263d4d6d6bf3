#!/usr/bin/env python3
"""Plots bench-results/scaling.csv (from `cargo bench --bench scene -- scaling CSV`) as an SVG:
query time per frame against the number of bodies, log-log, one line per thread count, with
the slope-1 (linear) and slope-2 (every body pair) references through the first point.
  python3 bench/scaling_plot.py bench-results/scaling.csv bench-results/scaling.svg"""
import csv
import math
import sys

src, dst = sys.argv[1], sys.argv[2]
rows = list(csv.DictReader(open(src)))
series = {}
for r in rows:
    series.setdefault(int(r["threads"]), []).append((int(r["bodies"]), float(r["query_ms"])))
W, H, L, B, T, R = 640, 420, 70, 50, 30, 150
xs = [x for s in series.values() for x, _ in s]
ys = [y for s in series.values() for _, y in s]
x0, x1 = math.log10(min(xs)), math.log10(max(xs))
y0, y1 = math.log10(min(ys)) - 0.2, math.log10(max(ys)) + 0.4
px = lambda x: L + (math.log10(x) - x0) / (x1 - x0) * (W - L - R)
py = lambda y: H - B - (math.log10(y) - y0) / (y1 - y0) * (H - B - T)
out = ['<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" font-family="sans-serif" font-size="12">' % (W, H)]
out.append('<rect width="100%" height="100%" fill="white"/>')
out.append('<line x1="%d" y1="%d" x2="%d" y2="%d" stroke="black"/>' % (L, H - B, W - R, H - B))
out.append('<line x1="%d" y1="%d" x2="%d" y2="%d" stroke="black"/>' % (L, T, L, H - B))
for e in range(math.floor(x0), math.ceil(x1) + 1):
    for m in (1, 3):
        v = m * 10 ** e
        if min(xs) <= v <= max(xs):
            out.append('<text x="%.1f" y="%d" text-anchor="middle">%g</text>' % (px(v), H - B + 16, v))
for e in range(math.floor(y0), math.ceil(y1) + 1):
    v = 10.0 ** e
    if 10 ** y0 <= v <= 10 ** y1:
        out.append('<text x="%d" y="%.1f" text-anchor="end">%g</text>' % (L - 6, py(v) + 4, v))
        out.append('<line x1="%d" y1="%.1f" x2="%d" y2="%.1f" stroke="#ddd"/>' % (L, py(v), W - R, py(v)))
out.append('<text x="%d" y="%d" text-anchor="middle">bodies (spheres of 484 triangles, each touching its neighbours)</text>' % ((L + W - R) / 2, H - 12))
out.append('<text x="16" y="%d" transform="rotate(-90 16 %d)" text-anchor="middle">query ms per frame (exact, median)</text>' % ((T + H - B) / 2, (T + H - B) / 2))
colors = {1: "#1f77b4", 2: "#d62728"}
first = min(series)
bx, by = sorted(series[first])[0]
for slope, dash, label in ((1, "4,3", "linear"), (2, "1,3", "n\u00b2 (every body pair)")):
    ex = max(xs)
    ey = by * (ex / bx) ** slope
    if ey > 10 ** y1:
        ex = bx * (10 ** y1 / by) ** (1 / slope)
        ey = 10 ** y1
    out.append('<line x1="%.1f" y1="%.1f" x2="%.1f" y2="%.1f" stroke="gray" stroke-dasharray="%s"/>' % (px(bx), py(by), px(ex), py(ey), dash))
    out.append('<text x="%.1f" y="%.1f" fill="gray">%s</text>' % (px(ex) + 4, py(ey) + 4, label))
for i, (t, pts) in enumerate(sorted(series.items())):
    pts.sort()
    c = colors.get(t, "black")
    out.append('<polyline fill="none" stroke="%s" stroke-width="2" points="%s"/>' % (c, " ".join("%.1f,%.1f" % (px(x), py(y)) for x, y in pts)))
    for x, y in pts:
        out.append('<circle cx="%.1f" cy="%.1f" r="3" fill="%s"/>' % (px(x), py(y), c))
    out.append('<text x="%d" y="%d" fill="%s">%d thread%s</text>' % (W - R + 10, T + 16 * i + 10, c, t, "" if t == 1 else "s"))
out.append("</svg>")
open(dst, "w").write("\n".join(out) + "\n")
