// setbound — the constrained-zonotope estimators in C++ (issue 21's benchmarks): per data set
// the time per step of CZN-A/CZN-B with the default limits (update(), which includes the interval
// hull), the mean interval-hull width as a ratio to the exact consistent set's hull (where that is
// tractable) and to the zonotopic methods (segment minimisation, volume minimisation, P-radius),
// the memory over 10 000 steps with limits, and the LP engines side by side on the same hull LPs
// (BoxLP against the interior-point LP of include/setbound/lmi/lp.hpp). Built only with
// -DSETBOUND_BUILD_BENCH=ON.
//
//   bench_czono_cpp [DATA_DIR] [--reps R] [--only NAME] [--no-exact] [--mem-steps N]
//                   [--update-doc docs/benchmarks.md]
//
// Ratios are of means over all steps and coordinates: mean width of the method / mean width of
// the reference (< 1: the constrained zonotope is tighter). The exact hull (polytopic/exact_hull.hpp: 2 n_x
// interior-point LPs per step, growing with k) is computed on the first `exact_horizon` steps of
// a record, and every ratio to it is over those steps.
#include <malloc.h>
#include <sys/resource.h>

#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "bench_stats.hpp"
#include "setbound/core/linear_system.hpp"
#include "setbound/estimators/constrained_zonotopic/estimator.hpp"
#include "setbound/estimators/polytopic/exact_hull.hpp"
#include "setbound/estimators/zonotopic/pradius.hpp"
#include "setbound/estimators/zonotopic/volume_min.hpp"
#include "setbound/estimators/zonotopic/gain_estimator.hpp"
#include "setbound/lmi/lp.hpp"
#include "setbound/sets/box_lp.hpp"
#include "cora_data.hpp"

using namespace setbound;
using namespace setbound_bench;  // Json, Benchmark, load: CORA's data in setbound's form
using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

// ---- records: CORA's data, the papers' §3.5 example, seeded random systems -------------------
struct Record {
  std::string name;
  std::unique_ptr<LinearSystem> system;
  VectorXd p0;
  MatrixXd H0, Y, U;   // U: N × n_u (may have 0 columns)
  double order = 20;   // zonotope order of the zonotopic methods (CORA's where given)
  ZonotopeReduction red = ZonotopeReduction::Girard;
  Index exact_horizon = 0;  // 0: no exact hull
};

Record from_cora(Benchmark&& b, Index exact_horizon) {
  Record r;
  r.name = b.name;
  r.system = std::move(b.system);
  r.p0 = b.p0;
  r.H0 = b.H0;
  r.Y = b.Y;
  r.U = b.U;
  r.order = b.order;
  r.red = b.reduction.rfind("pca", 0) == 0 ? ZonotopeReduction::Pca : ZonotopeReduction::Girard;
  r.exact_horizon = std::min<Index>(exact_horizon, r.Y.rows());
  return r;
}

VectorXd box_draw(std::mt19937& rng, Index m) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  VectorXd w(m);
  for (Index i = 0; i < m; ++i) w(i) = u(rng);
  return w;
}

MatrixXd randn(Index r, Index c, std::mt19937& rng, double s) {
  std::normal_distribution<double> g;
  MatrixXd M(r, c);
  for (Index i = 0; i < r; ++i)
    for (Index j = 0; j < c; ++j) M(i, j) = s * g(rng);
  return M;
}

// Simulates x+ = A x + E ω, y = C x + F ω from x0 uniform in the initial box, ω uniform.
void simulate(Record& r, Index N, std::mt19937& rng) {
  const LinearSystem& s = *r.system;
  VectorXd x = r.p0 + r.H0 * box_draw(rng, r.H0.cols());
  r.Y.resize(N, s.ny());
  r.U.resize(N, 0);
  for (Index k = 0; k < N; ++k) {
    const VectorXd w = box_draw(rng, s.nw());
    r.Y.row(k) = (s.C() * x + s.F() * w).transpose();
    x = s.A() * x + s.E() * box_draw(rng, s.nw());
  }
}

// papers.md §3.5 (EX-LE13) with a known A: x+ = [0 −0.5; 1 1] x + (−0.12, 0.02) w,
// y = [−2 1; 1 1] x + 0.2 v, X0 = 3·B², as bench/bench_zonotopic.py.
Record le13(Index N, unsigned seed) {
  MatrixXd A(2, 2), C(2, 2), E(2, 3), F(2, 3);
  A << 0, -0.5, 1, 1;
  C << -2, 1, 1, 1;
  E << -0.12, 0, 0, 0.02, 0, 0;
  F << 0, 0.2, 0, 0, 0, 0.2;
  Record r;
  r.name = "papers §3.5 (EX-LE13)";
  r.system = std::make_unique<LinearSystem>(A, C, E, F);
  r.p0 = VectorXd::Zero(2);
  r.H0 = 3.0 * MatrixXd::Identity(2, 2);
  r.exact_horizon = N;
  std::mt19937 rng(seed);
  simulate(r, N, rng);
  return r;
}

// A random system as tests/cpp/test_constrained_zonotopic.cpp: ‖A‖ <= 0.9, E = [E_d, 0],
// F = [0, F_v], X0 = 2·Bⁿ.
Record random_system(Index n, Index ny, Index N, unsigned seed) {
  std::mt19937 rng(seed);
  MatrixXd A = randn(n, n, rng, 1.0);
  A *= 0.9 / std::max(1.0, A.operatorNorm());
  const MatrixXd C = randn(ny, n, rng, 1.0);
  MatrixXd E = MatrixXd::Zero(n, n + ny), F = MatrixXd::Zero(ny, n + ny);
  E.leftCols(n) = randn(n, n, rng, 0.05);
  F.rightCols(ny) = (0.02 + 0.1 * randn(ny, 1, rng, 1.0).cwiseAbs().array()).matrix().asDiagonal();
  Record r;
  r.name = "random n=" + std::to_string(n) + " p=" + std::to_string(ny) + " seed " + std::to_string(seed);
  r.system = std::make_unique<LinearSystem>(A, C, E, F);
  r.p0 = VectorXd::Zero(n);
  r.H0 = 2.0 * MatrixXd::Identity(n, n);
  r.exact_horizon = N;
  simulate(r, N, rng);
  return r;
}

VectorXd urow(const Record& r, Index k) { return r.U.cols() ? VectorXd(r.U.row(k).transpose()) : VectorXd(0); }

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

struct Hulls {
  MatrixXd lo, hi;
  double mean_width(Index steps) const { return (hi.topRows(steps) - lo.topRows(steps)).mean(); }
};

struct CzRun {
  Hulls hull;
  double median_us = NAN;  // median over the repetitions of the mean time per step
  double p90_us = NAN;     // 90th percentile of single steps (all repetitions)
  Index max_gens = 0, max_rows = 0;
  bool finite = true;
};

CzRun run_czono(const Record& r, CZCorrection corr, int reps) {
  CZOptions opt;  // the default limits
  opt.correction = corr;
  const Index N = r.Y.rows(), n = r.system->nx();
  CzRun out;
  out.hull = {MatrixXd(N, n), MatrixXd(N, n)};
  std::vector<double> per_rep, steps;
  for (int rep = 0; rep < reps; ++rep) {
    ConstrainedZonotopicEstimator est(*r.system, ConstrainedZonotope(Zonotope(r.p0, r.H0)), opt);
    double total = 0;
    for (Index k = 0; k < N; ++k) {
      const VectorXd u = urow(r, k);
      const auto t0 = std::chrono::steady_clock::now();
      est.update(r.Y.row(k).transpose(), u);
      const double us = seconds_since(t0) * 1e6;
      total += us;
      steps.push_back(us);
      if (rep == 0) {
        out.hull.lo.row(k) = est.current_lower().transpose();
        out.hull.hi.row(k) = est.current_upper().transpose();
        out.max_gens = std::max(out.max_gens, est.current_set().num_generators());
        out.max_rows = std::max(out.max_rows, est.current_set().num_constraints());
      }
    }
    per_rep.push_back(total / static_cast<double>(N));
  }
  out.median_us = median(per_rep);
  std::sort(steps.begin(), steps.end());
  out.p90_us = steps[static_cast<std::size_t>(0.9 * static_cast<double>(steps.size() - 1))];
  out.finite = out.hull.lo.allFinite() && out.hull.hi.allFinite();
  return out;
}

// A zonotopic method on the same record (CORA's limit order·n_x and reduction technique).
bool run_zono(const Record& r, const ZonotopeGain& gain, const std::vector<Index>& strip_order, Hulls& h,
              double order = 0) {
  ZonotopicOptions opt;
  const Index n = r.system->nx();
  if (order <= 0) order = r.order;
  opt.max_generators = std::max<Index>(static_cast<Index>(order * static_cast<double>(n) + 1e-9), n);
  opt.reduction = r.red;
  opt.strip_order = strip_order;
  ZonotopicEstimator est(*r.system, Zonotope(r.p0, r.H0), gain, opt);
  const Index N = r.Y.rows();
  h = {MatrixXd(N, n), MatrixXd(N, n)};
  for (Index k = 0; k < N; ++k) {
    est.update(r.Y.row(k).transpose(), urow(r, k));
    h.lo.row(k) = est.current_lower().transpose();
    h.hi.row(k) = est.current_upper().transpose();
  }
  return true;
}

// The exact consistent set's hull on the first H steps: CZN-A without reduction (the exact set,
// tests/cpp/test_constrained_zonotopic.cpp WithoutReductionItIsTheExactConsistentSet), whose
// LPs stay tractable longer than exact_hull's growing interior-point LPs; exact_hull itself (an
// independent computation) on the first `check` steps, and their largest difference.
ExactHull exact_reference(const Record& r, Index H, Index check, double& diff) {
  CZOptions opt;
  opt.reduction = CZReduction::None;
  ConstrainedZonotopicEstimator est(*r.system, ConstrainedZonotope(Zonotope(r.p0, r.H0)), opt);
  const Index n = r.system->nx();
  ExactHull e{MatrixXd(H, n), MatrixXd(H, n)};
  for (Index k = 0; k < H; ++k) {
    est.update(r.Y.row(k).transpose(), urow(r, k));
    e.lower.row(k) = est.current_lower().transpose();
    e.upper.row(k) = est.current_upper().transpose();
  }
  const Index c = std::min(check, H);
  const ExactHull ip = exact_hull(*r.system, Zonotope(r.p0, r.H0), r.Y.topRows(c), r.U.topRows(c));
  diff = std::max(diff, std::max((ip.lower - e.lower.topRows(c)).cwiseAbs().maxCoeff(),
                                 (ip.upper - e.upper.topRows(c)).cwiseAbs().maxCoeff()));
  return e;
}

std::string fmt(double v, const char* f) {
  if (std::isnan(v)) return "—";
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

// ---- memory over a long run ---------------------------------------------------------------
struct MemoryRow {
  std::string name;
  Index steps;
  double rss0_kib, rss1_kib, heap_k_kib, heap_n_kib, us;
  Index gens, rows;
};

double heap_in_use_kib() {
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 33))
  return static_cast<double>(mallinfo2().uordblks) / 1024.0;
#else
  return NAN;
#endif
}

double maxrss_kib() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss);
}

// `steps` steps of CZN-A (default limits) on the record's system, simulated with uniform
// disturbances (the data's inputs repeated): peak RSS and heap in use after the first 1 000 steps
// and at the end.
MemoryRow memory_run(const Record& r, Index steps) {
  const LinearSystem& s = *r.system;
  std::mt19937 rng(7);
  ConstrainedZonotopicEstimator est(s, ConstrainedZonotope(Zonotope(r.p0, r.H0)));
  VectorXd x = r.p0 + r.H0 * box_draw(rng, r.H0.cols());
  MemoryRow m{r.name, steps, 0, 0, 0, 0, 0, 0, 0};
  const auto t0 = std::chrono::steady_clock::now();
  for (Index k = 0; k < steps; ++k) {
    const VectorXd u = urow(r, k % r.Y.rows());
    const VectorXd w = box_draw(rng, s.nw());
    VectorXd y = s.C() * x + s.F() * w;
    if (s.nu() > 0 && s.D().size()) y += s.D() * u;
    est.update(y, u);
    if (!((x.array() >= est.current_lower().array() - 1e-9).all() && (x.array() <= est.current_upper().array() + 1e-9).all()))
      throw std::runtime_error(r.name + ": the truth left the hull at step " + std::to_string(k));
    x = s.A() * x + s.E() * box_draw(rng, s.nw());
    if (s.nu() > 0) x += s.B() * u;
    m.gens = std::max(m.gens, est.current_set().num_generators());
    m.rows = std::max(m.rows, est.current_set().num_constraints());
    if (k + 1 == 1000) {
      m.rss0_kib = maxrss_kib();
      m.heap_k_kib = heap_in_use_kib();
    }
  }
  m.us = seconds_since(t0) * 1e6 / static_cast<double>(steps);
  m.rss1_kib = maxrss_kib();
  m.heap_n_kib = heap_in_use_kib();
  return m;
}

// ---- LP engines on the same hull LPs --------------------------------------------------------
struct LpRow {
  std::string name;
  Index sets, n, gens, rows;
  double boxlp_us, ipm_us, max_diff;
};

// Interval hulls of `sets` with BoxLP (ConstrainedZonotope::interval_hull: 2n LPs on one
// warm-started basis) and with the interior-point LP (2n LPs, each built and solved anew).
LpRow lp_compare(const std::string& name, const std::vector<ConstrainedZonotope>& sets) {
  LpRow row{name, static_cast<Index>(sets.size()), sets.front().dimension(), 0, 0, 0, 0, 0};
  double t_box = 0, t_ipm = 0, diff = 0;
  for (const ConstrainedZonotope& Z : sets) {
    row.gens = std::max(row.gens, Z.num_generators());
    row.rows = std::max(row.rows, Z.num_constraints());
    auto t0 = std::chrono::steady_clock::now();
    const BoundingBox hb = Z.interval_hull();
    t_box += seconds_since(t0);
    t0 = std::chrono::steady_clock::now();
    const Index n = Z.dimension(), m = Z.num_generators(), q = Z.num_constraints();
    for (Index i = 0; i < n; ++i)
      for (int sign : {-1, 1}) {
        lmi::LinearProgram lp(static_cast<int>(m));
        for (int v = 0; v < m; ++v) lp.add_bounds(v, -1.0, 1.0);
        for (Index k = 0; k < q; ++k) {
          lmi::LpRow rw;
          for (Index j = 0; j < m; ++j)
            if (Z.constraint_matrix()(k, j) != 0.0) rw.emplace_back(static_cast<int>(j), Z.constraint_matrix()(k, j));
          lp.add_eq(std::move(rw), Z.constraint_vector()(k));
        }
        lp.set_objective(sign * Z.generators().row(i).transpose());
        const lmi::SolveResult res = lp.solve();
        const double v = Z.center()(i) + sign * res.objective;  // min ±G_i ξ
        diff = std::max(diff, std::abs(v - (sign > 0 ? hb.lo(i) : hb.hi(i))));
      }
    t_ipm += seconds_since(t0);
  }
  const double s = static_cast<double>(sets.size());
  row.boxlp_us = t_box / s * 1e6;
  row.ipm_us = t_ipm / s * 1e6;
  row.max_diff = diff;
  return row;
}

std::vector<ConstrainedZonotope> sets_of(const Record& r, Index count) {
  ConstrainedZonotopicEstimator est(*r.system, ConstrainedZonotope(Zonotope(r.p0, r.H0)));
  std::vector<ConstrainedZonotope> out;
  const Index N = r.Y.rows();
  for (Index k = 0; k < N; ++k) {
    est.update(r.Y.row(k).transpose(), urow(r, k));
    if (k >= N - count) out.push_back(est.current_set());
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  std::string dir;
  if (const char* env = std::getenv("SETBOUND_CORA_DATA")) dir = env;
#ifdef SETBOUND_CORA_DATA_DEFAULT
  if (dir.empty()) dir = SETBOUND_CORA_DATA_DEFAULT;
#endif
  int reps = 5;
  Index mem_steps = 10000, check_steps = 15;
  double ref_check = 0.0;
  bool exact = true, skip_lp = false, skip_mem = false;
  std::string doc, only;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--reps" && i + 1 < argc) reps = std::stoi(argv[++i]);
    else if (a == "--only" && i + 1 < argc) only = argv[++i];
    else if (a == "--mem-steps" && i + 1 < argc) mem_steps = std::stol(argv[++i]);
    else if (a == "--no-exact") exact = false;
    else if (a == "--no-lp") skip_lp = true;
    else if (a == "--no-mem") skip_mem = true;
    else if (a == "--update-doc" && i + 1 < argc) doc = argv[++i];
    else dir = a;
  }
  std::vector<Record> recs;
  // The exact set's LPs grow with k (n_w + n_y unknowns and n_y rows per step): its horizon is
  // cut where one record's reference would take minutes.
  const std::vector<std::pair<std::string, Index>> cora = {
      {"alamo2005_2d", 20}, {"vehicle2_cora_unittest", 100}, {"pedestrian4", 100}, {"vehicle6", 80}, {"tank30", 0}};
  for (const auto& [name, horizon] : cora) recs.push_back(from_cora(load(dir + "/" + name + ".json", name), horizon));
  recs.push_back(le13(100, 1));
  unsigned seed = 1;
  for (Index n = 2; n <= 4; ++n)
    for (int t = 0; t < 3; ++t, ++seed) recs.push_back(random_system(n, 1 + (t % 2), 100, seed));

  std::ostringstream acc;
  acc << "| data | n_x | steps | CZN-A µs/step | p90 µs | gens/rows | exact steps | CZN-A / exact | CZN-B / exact | "
         "CZN-A / segment min. | CZN-A / volume min. | CZN-A / P-radius |\n"
         "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  std::vector<Record*> for_lp, for_mem;
  std::string vol_note;
  for (Record& r : recs) {
    if (!only.empty() && r.name.find(only) == std::string::npos) continue;
    const Index n = r.system->nx(), N = r.Y.rows();
    std::fprintf(stderr, "%s ...\n", r.name.c_str());
    const CzRun a = run_czono(r, CZCorrection::ExactOutput, reps);
    const CzRun b = run_czono(r, CZCorrection::WangStrips, 1);
    Index H = exact ? r.exact_horizon : 0;
    double ra = NAN, rb = NAN;
    if (H > 0) {
      const ExactHull e = exact_reference(r, H, check_steps, ref_check);
      const Hulls eh{e.lower, e.upper};
      ra = a.hull.mean_width(H) / eh.mean_width(H);
      rb = b.hull.mean_width(H) / eh.mean_width(H);
      // Every hull must contain the exact one (the guarantee), up to the LP tolerance.
      const double slack = 1e-7 * std::max(1.0, e.upper.cwiseAbs().maxCoeff());
      if (((a.hull.lo.topRows(H) - e.lower).array() > slack).any() || ((e.upper - a.hull.hi.topRows(H)).array() > slack).any())
        std::fprintf(stderr, "%s: CZN-A's hull does not contain the exact hull!\n", r.name.c_str());
    }
    const double wa = a.hull.mean_width(N);
    auto ratio_to = [&](const ZonotopeGain& g, const std::vector<Index>& order, double zorder = 0) {
      Hulls h;
      run_zono(r, g, order, h, zorder);
      return wa / h.mean_width(N);
    };
    const double rseg = ratio_to(ZonotopeGain(segment_min_gain), {});
    // Volume minimisation enumerates (n_x − 1)-subsets of the generators (at most 20 000): at
    // CORA's order where that fits, else at order 8, else not at all.
    double rvol = NAN;
    for (double zorder : {r.order, 8.0}) {
      try {
        rvol = ratio_to(ZonotopeGain(volume_min_gain), {}, zorder);
        if (zorder != r.order) vol_note += " " + r.name;
        break;
      } catch (const InvalidArgumentError&) {
      }
    }
    double rpr = NAN;
    if (n <= 6) try {  // the P-radius design's LMIs: only for small n_x
      const PRadiusDesign d = design_pradius(*r.system);
      rpr = ratio_to(pradius_gain(d), d.strip_order);
    } catch (const std::exception&) {
      // no contracting design for this system: no P-radius column
    }
    acc << "| " << r.name << " | " << n << " | " << N << " | " << fmt(a.median_us, "%.1f") << " | "
        << fmt(a.p90_us, "%.1f") << " | " << a.max_gens << "/" << a.max_rows << " | " << (H > 0 ? std::to_string(H) : "—")
        << " | " << fmt(ra, "%.4f") << " | " << fmt(rb, "%.4f") << " | " << fmt(rseg, "%.3f") << " | "
        << fmt(rvol, "%.3f") << " | " << fmt(rpr, "%.3f") << " |\n";
    if (r.name == "pedestrian4" || r.name == "vehicle6" || r.name == "tank30") for_lp.push_back(&r), for_mem.push_back(&r);
  }

  std::ostringstream mem;
  if (!skip_mem && mem_steps > 0) {
    mem << "| data | steps | µs/step | max gens/rows | max RSS after 1 000 steps | max RSS at the end | heap in use after 1 000 | heap in use at the end |\n"
           "|---|---|---|---|---|---|---|---|\n";
    for (Record* r : for_mem) {
      if (r->name == "tank30") continue;  // 10 000 steps of tank30 take minutes
      std::fprintf(stderr, "memory %s ...\n", r->name.c_str());
      const MemoryRow m = memory_run(*r, mem_steps);
      mem << "| " << m.name << " | " << m.steps << " | " << fmt(m.us, "%.1f") << " | " << m.gens << "/" << m.rows
          << " | " << fmt(m.rss0_kib, "%.0f") << " KiB | " << fmt(m.rss1_kib, "%.0f") << " KiB | "
          << fmt(m.heap_k_kib, "%.0f") << " KiB | " << fmt(m.heap_n_kib, "%.0f") << " KiB |\n";
    }
  }

  std::ostringstream lps;
  if (!skip_lp) {
    lps << "| sets from | sets | n_x | max gens | max rows | BoxLP µs/hull | interior point µs/hull | "
           "interior point / BoxLP | max difference |\n|---|---|---|---|---|---|---|---|---|\n";
    for (Record* r : for_lp) {
      std::fprintf(stderr, "LP engines %s ...\n", r->name.c_str());
      const LpRow l = lp_compare(r->name, sets_of(*r, r->name == "tank30" ? 3 : 20));
      lps << "| " << l.name << " | " << l.sets << " | " << l.n << " | " << l.gens << " | " << l.rows << " | "
          << fmt(l.boxlp_us, "%.1f") << " | " << fmt(l.ipm_us, "%.0f") << " | " << fmt(l.ipm_us / l.boxlp_us, "%.0f")
          << "× | " << fmt(l.max_diff, "%.1e") << " |\n";
    }
  }

  std::string loadavg = "unknown";
  if (std::ifstream la("/proc/loadavg"); la) {
    std::string x, y, z;
    la >> x >> y >> z;
    loadavg = x + " " + y + " " + z;
  }
  char when[64];
  const std::time_t now = std::time(nullptr);
  std::strftime(when, sizeof when, "%Y-%m-%d", std::localtime(&now));
  std::ostringstream out;
  out << "Generated by `build/cpp/bench_czono_cpp --reps " << reps << "` on " << when << ", "
      << std::thread::hardware_concurrency() << " hardware threads, load average " << loadavg
      << " at the end. CZN-A/B with the default limits (4 n_x rows, 24 n_x generators). µs/step: one "
      << "`update()` (screening, correction, reduction, interval hull, prediction), median over " << reps
      << " runs of the mean per step; p90 over single steps. Width ratios are of the mean interval-hull "
      << "width over steps and coordinates (< 1: CZN-A tighter); to the exact consistent set over its "
      << "first \"exact steps\" (the exact set: CZN-A without reduction, which matched the independent "
      << "interior-point `exact_hull` on the first " << check_steps << " steps of each record to "
      << fmt(ref_check, "%.1e") << "); zonotopic methods with order·n_x generators (CORA's order, 20 otherwise).\n\n"
      << acc.str()
      << (vol_note.empty() ? std::string() : "\nVolume minimisation at order 8 (CORA's order exceeds its subset limit):" + vol_note + ".\n");
  if (!mem.str().empty())
    out << "\nMemory over a long run (CZN-A, default limits, the system simulated with uniform "
           "disturbances; the truth inside every hull is checked):\n\n" << mem.str();
  if (!lps.str().empty())
    out << "\nLP engines on the same interval-hull LPs (2 n_x LPs per set, sets of the last steps of a CZN-A run): "
           "BoxLP (warm-started bounded simplex, certified by duality) against the interior-point LP "
           "(lmi/lp.hpp, each LP built and solved anew). \"max difference\": largest difference of a hull end.\n\n"
        << lps.str();
  std::printf("%s", out.str().c_str());
  if (!doc.empty()) {
    std::ifstream in(doc);
    std::stringstream ss;
    ss << in.rdbuf();
    std::string text = ss.str();
    const std::string begin = "<!-- bench_czono_cpp:begin -->", end = "<!-- bench_czono_cpp:end -->";
    const std::string block = begin + "\n" + out.str() + end;
    const auto a = text.find(begin), e = text.find(end);
    if (a != std::string::npos && e != std::string::npos) text.replace(a, e + end.size() - a, block);
    else text += "\n## Constrained zonotopes (C++)\n\n" + block + "\n";
    std::ofstream(doc) << text;
  }
  return 0;
}
