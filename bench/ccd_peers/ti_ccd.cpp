// ti_ccd: Tight-Inclusion's CCD (Wang et al., ACM TOG 2021; the peer in
// ../shared/peers/tight-inclusion, MIT) on every primitive query of the exact ground truth
// (../shared/meshes/sim/ccd: three simulation steps), timed the way glcollide's own timing
// test is (src/geom/ccd/tests/bench.rs), so that scripts/bench-ccd-peers.sh can put the two
// side by side.
//
//   ti_ccd TRUTH_DIR [GLC_TOI_DIR]
//
// Prints one tab-separated line per scene and kind (header first, '#'):
//   scene kind queries true ns_per_query median_wall_ns fp fn toi_zero max_itr_hit late below_max
// ns_per_query: the whole set's CPU time per query, best of 3. median_wall_ns: the median
// query's wall time (first pass). fp / fn: TI's booleans against the truth's. toi_zero: true answers with toi = 0.
// max_itr_hit: queries where TI stopped on max_itr before reaching its tolerance.
// With GLC_TOI_DIR (glcollide's tois, written by the ignored test `peer_columns`), TI's toi
// is compared with the exact earliest time t* on the queries both call true: glcollide's toi
// t is certified with t <= t* <= t + 2^-20, so `late` counts TI tois above t + 2^-20 (after
// the first contact: not the lower bound TI promises), `below_max` is the largest t - toi
// (how early TI's toi can be); '-' without the directory.
//
// TI's settings are the ones its authors recommend for a comparison (BUILD-HERE.md):
// tolerance 1e-6, max_itr 1e6, ms 0, err = (-1, -1, -1) (computed from each query),
// t_max 1, no_zero_toi false, breadth-first search.

#include <tight_inclusion/ccd.hpp>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <sys/stat.h>
#include <utility>
#include <vector>

namespace {

using ticcd::Vector3;

[[noreturn]] void die(const std::string &what)
{
    std::fprintf(stderr, "ti_ccd: %s\n", what.c_str());
    std::exit(1);
}

bool exists(const std::string &path)
{
    struct stat st;
    return stat(path.c_str(), &st) == 0;
}

std::string read_all(const std::string &path)
{
    std::ifstream in(path, std::ios::binary);
    if (!in) die("cannot read " + path);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

// A decimal integer as the double it is exactly, or fail: strtod rounds correctly, and
// glibc's "%.0f" prints a double's exact integer value, so the string comes back unchanged
// if and only if the integer is a double. (The ground truth's numerators fit in 53 bits and
// its denominators are powers of two, but that is the files' promise: checked, not assumed.)
double exact_integer(const std::string &s, const std::string &where)
{
    errno = 0;
    char *end = nullptr;
    const double x = std::strtod(s.c_str(), &end);
    if (s.empty() || *end != '\0' || errno != 0 || !std::isfinite(x))
        die(where + ": not a finite number: '" + s + "'");
    char back[512];
    std::snprintf(back, sizeof back, "%.0f", x);
    if (s != back) die(where + ": " + s + " is not exactly a double");
    return x;
}

// num / den, exactly: den a positive power of two (so the division only moves the exponent)
// and the quotient times den gives num back (no bit lost below the subnormal range).
double exact_ratio(const std::string &num, const std::string &den, const std::string &where)
{
    const double n = exact_integer(num, where), d = exact_integer(den, where);
    int e;
    if (!(d > 0) || std::frexp(d, &e) != 0.5)
        die(where + ": denominator " + den + " is not a power of two");
    const double x = n / d;
    if (x * d != n) die(where + ": " + num + "/" + den + " is not exactly a double");
    return x;
}

// One query: the 8 points in TI's argument order (the CSV's row order: the four points at
// t = 0, then at t = 1), and the truth.
struct Query {
    Vector3 p[8];
    bool truth;
};

std::vector<bool> booleans(const std::string &path)
{
    std::string text = read_all(path);
    for (char &c : text)
        if (c == '[' || c == ']' || c == ',') c = ' ';
    std::istringstream in(text);
    std::vector<bool> out;
    for (std::string w; in >> w;) {
        if (w == "true") out.push_back(true);
        else if (w == "false") out.push_back(false);
        else die(path + ": '" + w + "' is not a boolean");
    }
    return out;
}

// The points of a CSV: 8 rows a query, each x_num,x_den,y_num,y_den,z_num,z_den.
std::vector<std::vector<Vector3>> from_csv(const std::string &path)
{
    std::ifstream in(path);
    if (!in) die("cannot read " + path);
    std::vector<Vector3> rows;
    std::string line;
    for (size_t n = 1; std::getline(in, line); n++) {
        if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
        std::vector<std::string> f;
        std::istringstream ls(line);
        for (std::string cell; std::getline(ls, cell, ',');) f.push_back(cell);
        const std::string where = path + ":" + std::to_string(n);
        if (f.size() != 6) die(where + ": expected 6 fields");
        if (!f[5].empty() && f[5].back() == '\r') f[5].pop_back();
        rows.emplace_back(
            exact_ratio(f[0], f[1], where), exact_ratio(f[2], f[3], where),
            exact_ratio(f[4], f[5], where));
    }
    if (rows.size() % 8 != 0) die(path + ": rows not a multiple of 8");
    std::vector<std::vector<Vector3>> out;
    for (size_t i = 0; i < rows.size(); i += 8)
        out.emplace_back(rows.begin() + i, rows.begin() + i + 8);
    return out;
}

// The vertices of a part OBJ: its decimals are exact doubles (the README), so strtod's
// correctly rounded reading is that double (the same one glcollide's loader reads).
std::vector<Vector3> obj_vertices(const std::string &path)
{
    std::ifstream in(path);
    if (!in) die("cannot read " + path);
    std::vector<Vector3> v;
    std::string line;
    while (std::getline(in, line)) {
        if (line.rfind("v ", 0) != 0) continue;
        double x, y, z;
        if (std::sscanf(line.c_str() + 2, "%lf %lf %lf", &x, &y, &z) != 3)
            die(path + ": bad vertex line " + line);
        v.emplace_back(x, y, z);
    }
    return v;
}

// The edge-edge queries of a parts file (armadillo-rollers has no edge-edge CSV): part and
// the two vertex indices of each edge, the truth last; coordinates from the frames' OBJs.
std::vector<std::pair<std::vector<Vector3>, bool>>
ee_from_parts(const std::string &dir, const std::string &scene, int frame)
{
    const std::string path = dir + "/" + scene + "/" + std::to_string(frame) + "ee_parts.tsv";
    std::ifstream in(path);
    if (!in) die("cannot read " + path);
    std::map<std::pair<int, int>, std::vector<Vector3>> parts;
    auto vertex = [&](int f, int part, size_t i) -> const Vector3 & {
        auto &v = parts[{f, part}];
        if (v.empty()) {
            char name[64];
            std::snprintf(name, sizeof name, "/frame%d_part%02d.obj", f, part);
            v = obj_vertices(dir + "/../" + scene + name);
        }
        if (i >= v.size()) die(path + ": vertex index out of range");
        return v[i];
    };
    std::vector<std::pair<std::vector<Vector3>, bool>> out;
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') continue;
        long c[7];
        std::istringstream ls(line);
        for (long &x : c)
            if (!(ls >> x)) die(path + ": bad line " + line);
        const std::pair<long, long> ids[4] = {
            {c[0], c[1]}, {c[0], c[2]}, {c[3], c[4]}, {c[3], c[5]}};
        std::vector<Vector3> p(8);
        for (int k = 0; k < 4; k++) {
            p[k] = vertex(frame, int(ids[k].first), size_t(ids[k].second));
            p[k + 4] = vertex(frame + 1, int(ids[k].first), size_t(ids[k].second));
        }
        out.emplace_back(std::move(p), c[6] == 1);
    }
    return out;
}

// glcollide's tois of one scene and kind, one line a query: '-' (apart) or the toi.
std::vector<double> glc_tois(const std::string &path)
{
    std::ifstream in(path);
    if (!in) die("cannot read " + path);
    std::vector<double> out;
    for (std::string w; in >> w;)
        out.push_back(w == "-" ? NAN : std::strtod(w.c_str(), nullptr));
    return out;
}

// TI with the recommended settings (see the top of the file).
struct Answer {
    bool hit;
    double toi, output_tolerance;
};
constexpr double TOLERANCE = 1e-6;
constexpr long MAX_ITR = 1000000;

template <bool VF> Answer ti(const Query &q)
{
    const ticcd::Array3 err(-1, -1, -1);
    Answer a{false, 0, 0};
    const auto &p = q.p;
    if constexpr (VF)
        a.hit = ticcd::vertexFaceCCD(
            p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], err, /*ms=*/0, a.toi,
            TOLERANCE, /*t_max=*/1, MAX_ITR, a.output_tolerance, /*no_zero_toi=*/false);
    else
        a.hit = ticcd::edgeEdgeCCD(
            p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], err, /*ms=*/0, a.toi,
            TOLERANCE, /*t_max=*/1, MAX_ITR, a.output_tolerance, /*no_zero_toi=*/false);
    return a;
}

// This thread's CPU time in ns: the same counter as glcollide's bench reads
// (/proc/thread-self/schedstat's first field, the scheduler's sum_exec_runtime), so that
// a loaded machine inflates neither side.
double cpu_ns()
{
    timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return double(t.tv_sec) * 1e9 + double(t.tv_nsec);
}

double wall_s()
{
    timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return double(t.tv_sec) + double(t.tv_nsec) * 1e-9;
}

// As glcollide's best_of_3: three runs, each repeating the whole set for at least 0.2 s
// (the CPU time advances in scheduler ticks), the best run's CPU ns per pass.
template <class F> double best_of_3(F f)
{
    double best = INFINITY;
    for (int r = 0; r < 3; r++) {
        const double c0 = cpu_ns(), w0 = wall_s();
        long n = 0;
        while (n == 0 || wall_s() - w0 < 0.2) {
            f();
            n++;
        }
        best = std::min(best, (cpu_ns() - c0) / double(n));
    }
    return best;
}

template <bool VF>
void run(const std::string &scene, const std::vector<Query> &qs, const std::string &toi_path)
{
    // The answers are kept from the timed passes themselves (a store per query, next to
    // TI's tens of microseconds at least), no pass of its own: TI takes milliseconds on
    // many queries, and the three timed runs (one pass each where a pass outlasts 0.2 s)
    // are already most of the script's couple of minutes.
    // The first pass also reads the wall clock around each query (vDSO, tens of ns) for the
    // median: TI's cost is heavy-tailed, the mean alone hides it.
    std::vector<Answer> ans(qs.size());
    std::vector<double> each(qs.size());
    bool first = true;
    const double ns = best_of_3([&] {
        for (size_t i = 0; i < qs.size(); i++) {
            const double w0 = first ? wall_s() : 0;
            ans[i] = ti<VF>(qs[i]);
            if (first) each[i] = (wall_s() - w0) * 1e9;
        }
        first = false;
    });
    std::sort(each.begin(), each.end());
    const double median = each.empty() ? 0 : each[each.size() / 2];

    size_t trues = 0, fp = 0, fn = 0, zero = 0, itr = 0;
    for (size_t i = 0; i < qs.size(); i++) {
        trues += qs[i].truth;
        fp += ans[i].hit && !qs[i].truth;
        fn += !ans[i].hit && qs[i].truth;
        zero += ans[i].hit && ans[i].toi == 0;
        itr += ans[i].output_tolerance > TOLERANCE;
    }

    std::string late = "-", below = "-";
    if (!toi_path.empty()) {
        const std::vector<double> glc = glc_tois(toi_path);
        if (glc.size() != qs.size()) die(toi_path + ": not one toi per query");
        size_t n_late = 0;
        double below_max = 0;
        for (size_t i = 0; i < qs.size(); i++) {
            if (!ans[i].hit || std::isnan(glc[i])) continue;
            n_late += ans[i].toi > glc[i] + std::ldexp(1.0, -20);
            below_max = std::max(below_max, glc[i] - ans[i].toi);
        }
        late = std::to_string(n_late);
        char b[32];
        std::snprintf(b, sizeof b, "%.3g", below_max);
        below = b;
    }

    std::printf(
        "%s\t%s\t%zu\t%zu\t%.0f\t%.0f\t%zu\t%zu\t%zu\t%zu\t%s\t%s\n", scene.c_str(),
        VF ? "vf" : "ee", qs.size(), trues, ns / double(std::max<size_t>(qs.size(), 1)), median,
        fp, fn, zero, itr, late.c_str(), below.c_str());
    std::fflush(stdout);
}

} // namespace

int main(int argc, char **argv)
{
    if (argc < 2 || argc > 3) die("usage: ti_ccd TRUTH_DIR [GLC_TOI_DIR]");
    const std::string dir = argv[1], toi_dir = argc == 3 ? argv[2] : "";
    // The scenes of src/geom/ccd/tests/truth.rs: folder and the step's first frame.
    const std::pair<const char *, int> scenes[] = {
        {"cloth-funnel", 227}, {"rod-twist", 3036}, {"armadillo-rollers", 326}};
    std::printf("#scene\tkind\tqueries\ttrue\tns_per_query\tmedian_wall_ns\tfp\tfn\ttoi_zero"
                "\tmax_itr_hit\tlate\tbelow_max\n");
    for (const auto &[scene, frame] : scenes) {
        for (const bool vf : {true, false}) {
            const std::string tag = vf ? "vf" : "ee";
            const std::string stem = dir + "/" + scene + "/" + std::to_string(frame) + tag;
            const std::string csv = stem + ".csv", json = stem + "_mma_bool.json";
            const std::string parts = stem + "_parts.tsv";
            if (!exists(json) || (!exists(csv) && (vf || !exists(parts)))) {
                std::fprintf(stderr, "ti_ccd: %s %s: no queries here, skipped\n", scene,
                             tag.c_str());
                continue;
            }
            const std::vector<bool> truth = booleans(json);
            std::vector<Query> qs;
            if (exists(csv)) {
                for (auto &p : from_csv(csv)) {
                    Query q;
                    std::copy(p.begin(), p.end(), q.p);
                    q.truth = false;
                    qs.push_back(q);
                }
            } else {
                // As glcollide's loader: the parts file's own truth column must agree.
                for (auto &[p, t] : ee_from_parts(dir, scene, frame)) {
                    Query q;
                    std::copy(p.begin(), p.end(), q.p);
                    q.truth = t;
                    qs.push_back(q);
                }
                for (size_t i = 0; i < qs.size() && i < truth.size(); i++)
                    if (qs[i].truth != truth[i]) die(parts + ": truth differs from " + json);
            }
            if (qs.size() != truth.size()) die(stem + ": not one boolean per query");
            for (size_t i = 0; i < qs.size(); i++) qs[i].truth = truth[i];
            const std::string toi =
                toi_dir.empty() ? "" : toi_dir + "/" + scene + "_" + tag + ".toi";
            if (vf) run<true>(scene, qs, toi);
            else run<false>(scene, qs, toi);
        }
    }
}
