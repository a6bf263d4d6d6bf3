#!/usr/bin/env python3
"""Turns the benchmark's CSV files into SUMMARY.md, results.json and SVG figures.
   python3 bench/summarize.py [DIR]    (DIR defaults to bench-results)
Standard library only (no numpy / matplotlib): the figures are hand-written SVG."""
import csv, json, math, os, sys

D = sys.argv[1] if len(sys.argv) > 1 else "bench-results"


def rd(name):
    p = os.path.join(D, name)
    if not os.path.exists(p):
        return []
    with open(p) as f:
        return list(csv.DictReader(f))


def num(x):
    try:
        v = float(x)
        return v if math.isfinite(v) else None
    except (TypeError, ValueError):
        return None


peers = rd("peers.csv")
parry = rd("parry.csv")
mem_rs = rd("memory_rust.csv")
scenes = []
gl_line = []
if os.path.exists(os.path.join(D, "scenes.tsv")):
    with open(os.path.join(D, "scenes.tsv")) as f:
        lines = [l.rstrip("\n") for l in f if not l.startswith("scene\t")]
    gl_line = [l for l in lines if l.startswith("#")]
    scenes = [l.split("\t") for l in lines if l and not l.startswith("#")]
machine = open(os.path.join(D, "machine.txt")).read() if os.path.exists(os.path.join(D, "machine.txt")) else ""
refit_md = open(os.path.join(D, "refit.md")).read() if os.path.exists(os.path.join(D, "refit.md")) else ""

# ---------------------------------------------------------------- SVG plotting
PAL = ["#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f", "#17becf", "#bcbd22"]


def esc(s):
    return str(s).replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


def fmt(v):
    if v == 0:
        return "0"
    a = abs(v)
    if a >= 1e6 or a < 1e-3:
        return "%.0e" % v
    if a >= 100:
        return "%.0f" % v
    return ("%.3g" % v)


def panel(x0, y0, w, h, series, title, xl, yl, logx=True, logy=True, floor=None, markers_only=False):
    """series: [(label, color, [(x, y, tag)])]; returns svg elements."""
    pts = [(p[0], p[1]) for _, _, s in series for p in s if p[0] is not None and p[1] is not None]
    out = []
    if not pts:
        out.append('<text x="%g" y="%g" font-size="12">%s: no data</text>' % (x0 + 10, y0 + 20, esc(title)))
        return out
    def tr(v, log, fl):
        if log:
            return math.log10(max(v, fl))
        return v
    fx = min(p[0] for p in pts if p[0] > 0) if logx else 0
    fy = floor if floor else (min([p[1] for p in pts if p[1] > 0] or [1]) if logy else 0)
    xs = [tr(p[0], logx, fx) for p in pts]
    ys = [tr(p[1], logy, fy) for p in pts]
    xa, xb = min(xs), max(xs)
    ya, yb = min(ys), max(ys)
    if logx:
        xa, xb = math.floor(xa), math.ceil(xb)
    if logy:
        ya, yb = math.floor(ya), math.ceil(yb)
    if not logy:
        ya = min(0, ya)
        yb = yb * 1.05 if yb > 0 else 1
    if xb == xa:
        xb = xa + 1
    if yb == ya:
        yb = ya + 1
    L, R, T, B = 62, 10, 24, 40
    pw, ph = w - L - R, h - T - B
    X = lambda v: x0 + L + (tr(v, logx, fx) - xa) / (xb - xa) * pw
    Y = lambda v: y0 + T + ph - (tr(v, logy, fy) - ya) / (yb - ya) * ph
    out.append('<rect x="%g" y="%g" width="%g" height="%g" fill="white" stroke="#333"/>' % (x0 + L, y0 + T, pw, ph))
    out.append('<text x="%g" y="%g" font-size="13" font-weight="bold" text-anchor="middle">%s</text>' % (x0 + L + pw / 2, y0 + 16, esc(title)))
    out.append('<text x="%g" y="%g" font-size="11" text-anchor="middle">%s</text>' % (x0 + L + pw / 2, y0 + h - 6, esc(xl)))
    out.append('<text x="%g" y="%g" font-size="11" text-anchor="middle" transform="rotate(-90 %g %g)">%s</text>' % (x0 + 12, y0 + T + ph / 2, x0 + 12, y0 + T + ph / 2, esc(yl)))
    def ticks(a, b, log):
        if log:
            return [10 ** k for k in range(int(a), int(b) + 1)]
        step = 10 ** math.floor(math.log10((b - a) / 4 or 1))
        for m in (1, 2, 5, 10):
            if (b - a) / (step * m) <= 6:
                step *= m
                break
        t, v = [], math.ceil(a / step) * step
        while v <= b + 1e-12:
            t.append(v)
            v += step
        return t
    for t in ticks(xa, xb, logx):
        px = X(t)
        out.append('<line x1="%g" y1="%g" x2="%g" y2="%g" stroke="#ddd"/>' % (px, y0 + T, px, y0 + T + ph))
        out.append('<text x="%g" y="%g" font-size="10" text-anchor="middle">%s</text>' % (px, y0 + T + ph + 13, fmt(t)))
    for t in ticks(ya, yb, logy):
        py = Y(t)
        lab = fmt(t)
        if floor and logy and abs(t - floor) < 1e-300:
            lab = "0"
        out.append('<line x1="%g" y1="%g" x2="%g" y2="%g" stroke="#ddd"/>' % (x0 + L, py, x0 + L + pw, py))
        out.append('<text x="%g" y="%g" font-size="10" text-anchor="end">%s</text>' % (x0 + L - 3, py + 3, lab))
    ly = y0 + T + 12
    for label, color, s in series:
        s = [p for p in s if p[0] is not None and p[1] is not None]
        if not s:
            continue
        if not markers_only and len(s) > 1:
            out.append('<polyline fill="none" stroke="%s" stroke-width="1.6" points="%s"/>' % (color, " ".join("%.1f,%.1f" % (X(p[0]), Y(p[1])) for p in s)))
        for p in s:
            out.append('<circle cx="%.1f" cy="%.1f" r="3" fill="%s"/>' % (X(p[0]), Y(p[1]), color))
            if len(p) > 2 and p[2]:
                out.append('<text x="%.1f" y="%.1f" font-size="8" fill="%s">%s</text>' % (X(p[0]) + 4, Y(p[1]) - 4, color, esc(p[2])))
        out.append('<rect x="%g" y="%g" width="10" height="3" fill="%s"/><text x="%g" y="%g" font-size="10">%s</text>' % (x0 + L + 6, ly - 4, color, x0 + L + 20, ly, esc(label)))
        ly += 13
    return out


def svg(name, w, h, parts, caption=""):
    body = ['<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" font-family="sans-serif">' % (w, h + (18 if caption else 0)),
            '<rect width="100%" height="100%" fill="white"/>'] + parts
    if caption:
        body.append('<text x="8" y="%d" font-size="10" fill="#444">%s</text>' % (h + 12, esc(caption)))
    body.append("</svg>")
    with open(os.path.join(D, name), "w") as f:
        f.write("\n".join(body))


# ---------------------------------------------------------------- data
ok = lambda r: not r["note"].startswith("unavailable")
main_rows = [r for r in peers if r["group"] in ("paper", "instrument", "heavy", "scaling") and ok(r)]
by_scene = {}
for r in main_rows + [r for r in parry]:
    by_scene.setdefault(r["scene"], []).append(r)
scene_order = [s[0] for s in scenes] or sorted(by_scene)
tris = {s[0]: (int(s[2]), int(s[3])) for s in scenes}
# parry's glcollide rows are a second measurement of glcollide (same frames, Rust API)


def glc(scene, src=""):
    for r in by_scene.get(scene, []):
        if r["engine"].startswith("glcollide") and r["group"] != "eps_sweep" and r.get("_src", "") == src:
            return r
    return None


def ratio_of(r):
    """peer total / glcollide total measured in the same process on the same frames"""
    g = glc(r["scene"], r.get("_src", ""))
    t = num(r["total_us"])
    if not g or g is r or not t or not num(g["total_us"]):
        return None
    return t / num(g["total_us"])


for r in parry:
    r["_src"] = "parry"
    r["engine"] = r["engine"] if r["engine"] != "glcollide" else "glcollide (Rust API, parry run)"

# ---------------------------------------------------------------- figure 2
leaf = [r for r in peers if r["group"] == "leaf_sweep" and ok(r)]
f2 = []
for i, (title, key) in enumerate([("query", "query_us"), ("update (refit, both meshes)", "update_us"), ("total (update + query)", "total_us")]):
    series = []
    for j, sc in enumerate([s for s in scene_order if any(r["scene"] == s for r in leaf)]):
        pts = sorted((int(r["leaf"]), num(r[key])) for r in leaf if r["scene"] == sc)
        series.append(("%s (%s tris)" % (sc.split("_vs_")[-1], tris.get(sc, ("", ""))[1]), PAL[j % len(PAL)], [(x, y) for x, y in pts]))
    f2 += panel((i % 2) * 440, (i // 2) * 300, 440, 300, series, title, "max polygons per box", "median µs per frame")
svg("fig2_polygons_per_box.svg", 880, 600, f2, "glcollide CPU backend, epsilon 0 (exact); instrument scissors_blade; medians over the frames; machine in SUMMARY.md")

# ---------------------------------------------------------------- figure 3
f3s = []
groups = [("glcollide", "glcollide"), ("fcl_aabb", "FCL AABB"), ("bullet_gimpact", "Bullet GImpact+exact"), ("embree_collide", "Embree rtcCollide+exact"), ("parry3d_f64", "parry3d-f64")]
inst = [r for r in main_rows + parry if r["group"] in ("paper", "scaling")]
for j, (eng, lab) in enumerate(groups):
    pts = sorted((int(r["tris_b"]), num(r["query_us"])) for r in inst if r["engine"] == eng)
    f3s.append((lab, PAL[j], [(x, y) for x, y in pts]))
f3 = panel(0, 0, 620, 380, f3s, "query time against mesh size (instrument vs mesh)", "triangles of the mesh", "median query µs")
ups = []
for j, (eng, lab) in enumerate(groups):
    pts = sorted((int(r["tris_b"]), num(r["update_us"])) for r in inst if r["engine"] == eng)
    ups.append((lab, PAL[j], [(x, y) for x, y in pts]))
f3 += panel(620, 0, 620, 380, ups, "update (refit) time against mesh size", "triangles of the mesh", "median update µs")
svg("fig3_query_vs_size.svg", 1240, 380, f3, "paper set (1.2k-52k) and the subdivided gallbladder (59k-941k), scissors_blade posed for ~12 colliding pairs; exact answers")

# ---------------------------------------------------------------- speed vs error
sweep = [r for r in peers if r["group"] == "eps_sweep"]
sweep_scenes = sorted({r["scene"] for r in sweep})
se = []
for i, sc in enumerate(sweep_scenes):
    series = []
    chk = lambda r: max(1, int(r["check_frames"] or 0))
    for j, eng in enumerate(["glcollide", "glcollide_gl_select", "glcollide_gl_compute"]):
        rs = sorted((num(r["eps_rel"]), r) for r in sweep if r["scene"] == sc and r["engine"] == eng and ok(r))
        series.append((eng.replace("glcollide_", "").replace("glcollide", "cpu") + " (label: eps/extent)", PAL[j],
                       [(num(r["query_us"]), int(r["extra"]) / chk(r) + 0.0, "%g" % e) for e, r in rs]))
    for j, (eng, lab) in enumerate(groups[1:]):
        rs = [r for r in by_scene.get(sc, []) if r["engine"] == eng]
        if rs:
            series.append((lab + " (exact)", PAL[3 + j], [(num(rs[0]["query_us"]), (int(rs[0]["extra"]) + int(rs[0]["missed"])) / chk(rs[0]), "")]))
    # floor 0.1 is drawn as "0"
    series = [(l, c, [(x, max(y, 0.1), t) for x, y, t in s]) for l, c, s in series]
    se += panel(i * 560, 0, 560, 380, series, sc, "median query µs", "extra pairs per frame (0 = exact)", floor=0.1, markers_only=False)
svg("speed_vs_error.svg", max(560, 560 * len(sweep_scenes)), 380, se, "missed pairs were 0 everywhere (see table); epsilon is relative to the scene's extent")

# ---------------------------------------------------------------- results.json
json.dump({"machine": machine, "scenes": [dict(zip(["scene", "group", "tris_a", "tris_b", "extent", "how"], s)) for s in scenes if not s[0].startswith("#")],
           "peers": peers, "parry": [{k: v for k, v in r.items() if k != "_src"} for r in parry], "memory_rust": mem_rs},
          open(os.path.join(D, "results.json"), "w"), indent=1)

# ---------------------------------------------------------------- SUMMARY.md
L = []
w = L.append
w("# glcollide benchmarks: speed against error, side by side with the peers\n")
w("Written by `bash scripts/bench.sh` (bench/summarize.py). Raw numbers: `peers.csv` (C++ program, one process per run: "
  "glcollide via the C API, FCL, Bullet, Embree), `parry.csv` and `memory_rust.csv` (Rust bench: parry3d-f64 and glcollide "
  "on the same frames), `refit.md`, all in `results.json`.\n")
w("## Machine\n")
w("```\n" + machine.strip() + ("\n" + gl_line[0].lstrip("# ") if gl_line else "") + "\n```\n")
w("Times are wall-clock medians over the frames of one run (2 untimed warm-up frames), one thread per library "
  "(Embree with `threads=1`). A load average above the core count means other processes shared the cores: "
  "treat ratios as more reliable than absolute numbers, and expect 20-50% run-to-run variation.\n")
w("## Scenes\n")
w("| scene | group | triangles (reference / other) | how it was made |\n|---|---|---|---|")
for s in scenes:
    if s[0].startswith("#"):
        continue
    w("| %s | %s | %s / %s | %s |" % (s[0], s[1], s[2], s[3], s[5]))
w("")
w("Frames: the organ deforms every frame (every vertex moves: `p + 0.002·extent·sin(phase + 6·p/extent)` per axis) and the "
  "instrument follows the surface point it touches while its depth oscillates ±30% and it slides sideways; the depth was "
  "chosen (bisection) so that the median exact answer is about 12 colliding pairs. Heavy case: colon and small intestine "
  "overlap at rest; both deform with opposite warps (amplitude 0.004·extent). Every library gets the same float positions "
  "(peers get them widened to double; conversions are outside the timed region, and Bullet/Embree read the caller's array in "
  "place). The exact answer comes from CGAL (`do_intersect(Triangle_3, Triangle_3)`, exact predicates) over all triangle pairs "
  "whose boxes overlap, on 8 evenly spaced frames of each run.\n")

w("## Side by side (exact answers)\n")
w("update = the libraries' update calls for both meshes; query = collision query plus whatever narrow phase gives the exact pair "
  "list. ratio = peer's median total / glcollide's median total measured in the same process on the same frames (> 1: "
  "glcollide faster; FCL, Bullet and Embree against the C-API glcollide row, parry against the Rust-API row of its own run). missed/extra: against the exact "
  "answer, summed over the checked frames.\n")
w("| scene | library | update µs | query µs | total µs | ratio | pairs/frame | missed / extra | bytes/polygon |\n|---|---|---:|---:|---:|---:|---:|---|---:|")
for sc in scene_order:
    rs = [r for r in by_scene.get(sc, []) if r["group"] != "eps_sweep"]
    g = glc(sc)
    if not rs:
        continue
    for r in rs:
        t = num(r["total_us"])
        ratio = ratio_of(r)
        bpp = num(r["bytes_per_polygon"]) or 0
        if not bpp and r["engine"] == "glcollide":
            bpp = next((num(m["bytes_per_polygon"]) for m in mem_rs if m["scene"] == sc and m["library"] == "glcollide"), 0)
        w("| %s | %s | %s | %s | %s | %s | %s | %s / %s | %s |" % (
            sc, r["engine"], fmt(num(r["update_us"]) or 0), fmt(num(r["query_us"]) or 0), fmt(t or 0),
            ("%.2f" % ratio) if ratio else "", r["pairs_median"], r["missed"], r["extra"],
            ("%.0f" % bpp) if bpp else ""))
w("")
unav = [r for r in peers if not ok(r)]
if unav:
    w("Not measured: " + "; ".join(sorted({"%s (%s): %s" % (r["engine"], r["scene"], r["note"]) for r in unav})) + "\n")

# targets
w("## Where we stand against the targets\n")
def row(sc, eng):
    for r in by_scene.get(sc, []):
        if r["engine"] == eng and r["group"] != "eps_sweep":
            return r
peer_names = ["fcl_aabb", "bullet_gimpact", "embree_collide", "parry3d_f64"]
def fastest_peer(sc):
    """the exact peer with the smallest ratio to its same-process glcollide"""
    best = None
    for e in peer_names:
        r = row(sc, e)
        if r and ratio_of(r) is not None and int(r["missed"]) == 0 and int(r["extra"]) == 0:
            if best is None or ratio_of(r) < ratio_of(best):
                best = r
    return best
w("| target | measured | met? |\n|---|---|---|")
rf = [r for r in mem_rs if r["library"] == "glcollide" and r["scene"] == "blade_vs_spine52k"]
if rf:
    v = num(rf[0]["refit_b_us"])
    w("| refit of a ~52k-triangle mesh < 50 µs | %s µs (`Mesh::refit` of spine52k, %s triangles, median of 200) | %s |" % (fmt(v), tris.get("blade_vs_spine52k", ("", ""))[1], "yes" if v is not None and v < 50 else "no"))
for sc, lab in [("blade_vs_spine52k", "full frame, instrument vs ~52k"), ("jaw_vs_spine52k", "full frame, forceps_jaw vs ~52k")]:
    g, p = glc(sc), fastest_peer(sc)
    if g:
        t = num(g["total_us"])
        w("| %s: update + query < 150 µs | %s µs (update %s + query %s) | %s |" % (lab, fmt(t), fmt(num(g["update_us"])), fmt(num(g["query_us"])), "yes" if t < 150 else "no"))
        if p:
            r = ratio_of(p)
            w("| %s: >= 3x faster than the fastest peer | %.1fx (fastest exact peer: %s, %s µs; vs glcollide %s µs in the same process) | %s |" % (lab, r, p["engine"], fmt(num(p["total_us"])), fmt(num(glc(sc, p.get("_src", ""))["total_us"])), "yes" if r >= 3 else "no"))
g, p = glc("colon_vs_small_intestine"), fastest_peer("colon_vs_small_intestine")
if g and p:
    r = ratio_of(p)
    g2 = glc("colon_vs_small_intestine", p.get("_src", ""))
    exact = int(g["missed"]) == 0 and int(g["extra"]) == 0
    w("| heavy case (colon vs small_intestine, 20k vs 20k): >= 3x faster than the fastest peer, exact | %.2fx (%s %s µs vs glcollide %s µs in the same process; glcollide query alone %s µs); answer %s | %s |" % (
        r, p["engine"], fmt(num(p["total_us"])), fmt(num(g2["total_us"])), fmt(num(g2["query_us"])), "exact" if exact else "NOT exact", "yes" if r >= 3 and exact else "no"))
w("")

w("## Figure 2: polygons per box (paper §3.1)\n")
w("![Figure 2](fig2_polygons_per_box.svg)\n")
w("| scene | " + " | ".join("leaf %s" % l for l in sorted({int(r["leaf"]) for r in leaf})) + " |")
w("|---|" + "---:|" * len({int(r["leaf"]) for r in leaf}))
for sc in [s for s in scene_order if any(r["scene"] == s for r in leaf)]:
    cells = []
    for l in sorted({int(r["leaf"]) for r in leaf}):
        rr = [r for r in leaf if r["scene"] == sc and int(r["leaf"]) == l]
        cells.append(("%s / %s" % (fmt(num(rr[0]["query_us"])), fmt(num(rr[0]["update_us"])))) if rr else "")
    w("| %s | %s |" % (sc, " | ".join(cells)))
w("\n(query µs / update µs, medians.) **The paper's shape:** query time is U-shaped in the number of polygons per box but "
  "flat over a wide range (\"not very sensitive\"): best around 300-600 polygons per box for objects above 5,000 polygons and "
  "50-150 below; update time is almost independent of it, since every polygon is processed whatever the box count; total "
  "follows query. Compare with the table: see the notes below for where ours differs.\n")

w("## Figure 3: query time against mesh size (paper §3.2)\n")
w("![Figure 3](fig3_query_vs_size.svg)\n")
w("**The paper's shape:** query time grows with the number of polygons, but far below linearly (1.2k to 52k triangles "
  "changed it only modestly), which the paper calls the main strength of the method; update is linear in the polygons.\n")

w("## Speed against error\n")
w("![speed vs error](speed_vs_error.svg)\n")
w("epsilon is the viewing-volume depth relative to the scene's largest extent (0 = exact intersection on the CPU backend; the GL "
  "backends raise anything below 2^-20·extent to that minimum). Errors against the exact CGAL answer on the checked frames: "
  "missed pairs, extra pairs, largest distance between the two triangles of an extra pair (absolute, and over the extent).\n")
w("| scene | backend | eps/extent | frames | query µs | update µs | pairs/frame | missed | extra | max extra distance | / extent |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
for r in sweep:
    if not ok(r):
        w("| %s | %s | | | | | | | | | %s |" % (r["scene"], r["engine"], r["note"]))
        continue
    ext = num(r["eps_abs"]) / num(r["eps_rel"]) if num(r["eps_rel"]) else None
    d = num(r["max_extra_dist"]) or 0
    w("| %s | %s | %g | %s | %s | %s | %s | %s | %s | %.3g | %s |" % (r["scene"], r["engine"], num(r["eps_rel"]), r["frames"], fmt(num(r["query_us"])), fmt(num(r["update_us"])),
      r["pairs_median"], r["missed"], r["extra"], d, ("%.2g" % (d / ext)) if ext and d else "0"))
w("\nThe peers (FCL-AABB, Bullet+exact, Embree+exact, parry3d-f64) have no epsilon: they were exact in every checked frame (table above).\n")

w("## Memory per polygon\n")
w("| scene | library | bytes | bytes/polygon | how counted |\n|---|---|---:|---:|---|")
for r in mem_rs:
    b = int(r["structure_bytes"]) + int(r["cache_bytes"] or 0)
    note = r["note"]
    if r["library"] == "glcollide":
        note = "structure %s B + CPU-backend box cache %s B; %s" % (r["structure_bytes"], r["cache_bytes"], r["note"])
    w("| %s | %s | %d | %s | %s |" % (r["scene"], r["library"], b, r["bytes_per_polygon"], note))
for r in main_rows:
    if r["engine"] in ("fcl_aabb", "bullet_gimpact", "embree_collide") and int(r["bytes"] or 0) > 0:
        w("| %s | %s | %s | %s | %s |" % (r["scene"], r["engine"], r["bytes"], r["bytes_per_polygon"], r["note"]))
w("")

w("## Findings (computed from this run)\n")
for r in main_rows + parry:
    if int(r["missed"] or 0) or int(r["extra"] or 0):
        w("- **%s on %s is not exact here**: %s missed / %s extra pairs over %s checked frames (against CGAL). For Bullet the likely "
          "cause is its 16-bit quantization frame, fixed at `buildSet()` and padded by 1.0 model unit: the moving instrument leaves "
          "its rest-pose frame and refit clamps its boxes into it (peers/REPORT.md saw no misses on spheres that stay in place)."
          % (r["engine"], r["scene"], r["missed"], r["extra"], r["check_frames"]))
for sc in [x for x in scene_order if any(r["scene"] == x for r in leaf)]:
    rr = sorted((int(r["leaf"]), num(r["update_us"]), num(r["query_us"])) for r in leaf if r["scene"] == sc)
    if len(rr) > 2:
        bq = min(rr, key=lambda t: t[2])
        w("- Figure 2, %s: update %s µs at %d polygons per box against %s µs at %d (the paper: almost independent); best query "
          "%s µs at %d per box." % (sc, fmt(rr[0][1]), rr[0][0], fmt(rr[-1][1]), rr[-1][0], fmt(bq[2]), bq[0]))
w("- Update falling with bigger boxes comes from the slot layout (src/bvh: every leaf stores its own copy of the vertices it "
  "uses): small leaves duplicate more shared vertices and add per-leaf overhead, so the refit walks more slots. The paper's "
  "update walked each polygon once.")
gl = [r for r in sweep if "gl_" in r["engine"] and ok(r)]
if gl:
    w("- GL backends (Mesa, see the Machine section): median query %s-%s µs, against %s-%s µs for the CPU backend on the same "
      "scenes; on a software renderer the CPU backend is the one to use (AUTO picks it)." % (
        fmt(min(num(r["query_us"]) for r in gl)), fmt(max(num(r["query_us"]) for r in gl)),
        fmt(min(num(r["query_us"]) for r in sweep if r["engine"] == "glcollide")), fmt(max(num(r["query_us"]) for r in sweep if r["engine"] == "glcollide"))))
w("")
w("## Refit per mesh (benches/refit.rs)\n")
w(refit_md.strip() + "\n")
open(os.path.join(D, "SUMMARY.md"), "w").write("\n".join(L) + "\n")
print("wrote", os.path.join(D, "SUMMARY.md"))
