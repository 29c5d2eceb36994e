// setbound — C++ time per step of the estimator classes behind CORA's observer names
// (setbound.cora.algorithms(); spec cora_observers.md §0) on CORA's linearSysDT observer data
// (shared/benchmarks/cora_linearSysDT_observe). Built only with -DSETBOUND_BUILD_BENCH=ON;
// bench/bench_cora.py runs it and puts its figures next to the Python ones in docs/cora_comparison.md.
//
//   bench_cora_cpp [DATA_DIR] [--models a,b,...] [--methods A,B,...] [--min-steps N]
//                  [--max-seconds S] [--json FILE]
//
// Every method is built as the default convention of setbound.cora.observe builds it (the
// guaranteed estimators, CORA's zonotope order and reduction technique of the model file):
//   FRad-A, VolMin-A, VolMin-B, FRad-B, FRad-C   ZonotopicObserver (SegmentMin, VolumeMin, Bravo,
//                       Wang, Combastel)
//   PRad-A, PRad-B, PRad-E, Nom-G   design_zonotopic_gain, then ZonotopicObserver with the fixed
//                       gain (FixedStrips, FixedLambda, FixedGain); PRad-C/D have no design in
//                       setbound: run with CORA's saved SDPT3 gains where those exist (vehicle2)
//   Hinf-G              thesis::IntervalLuenbergerObserver with hinf_observer_gain (Tang 2019's H∞ gain)
//   ESO-A / ESO-B       BoundingEllipsoidEstimator (Gollamudi / Liu), enclosing ellipsoids of R0, W, V
//   ESO-C               thesis::design_ellipsoidal_sm_observer + EllipsoidalSMObserver (Loukkas 2017)
//   CZN-A / CZN-B       ConstrainedZonotopicEstimator (exact output / Wang strips, bounded mode)
//   ROPO                ParallelotopeEstimator (Vicino–Zappa), the model's reduction technique
// (Rauch-Tung-Striebel / RTS smooth a whole record, not step by step: no C++ per-step row.)
// The design (where there is one) is timed once, outside the per-step clock (as CORA's
// evaluateSingleObserver, spec §4.1). Each step (one update()/step() call) is timed with a steady
// clock; whole horizons are repeated until at least N steps are timed (default 400) or S seconds
// (default 20) have passed; the median and the 90th percentile are printed. A method that cannot
// be built on a model (no design, infeasible design, unsupported model) gets a row with the error.
// Output: one JSON object on stdout (or FILE): machine, load average, and the rows.
#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <exception>
#include <fstream>
#include <functional>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "bench_stats.hpp"
#include "cora_data.hpp"
#include "setbound/core/convention.hpp"
#include "setbound/estimators/constrained_zonotopic/estimator.hpp"
#include "setbound/estimators/ellipsoidal/bounding_ellipsoid.hpp"
#include "setbound/estimators/zonotopic/designs.hpp"
#include "setbound/estimators/zonotopic/observer.hpp"
#include "setbound/estimators/zonotopic/parallelotope.hpp"
#include "setbound/sets/box.hpp"
#include "setbound/sets/constrained_zonotope.hpp"
#include "setbound/thesis/eso_d.hpp"
#include "setbound/thesis/hinf_gain.hpp"
#include "setbound/thesis/hinf_observer.hpp"
#include "setbound/thesis/interval_observer.hpp"
#include "setbound/thesis/plant.hpp"

using namespace setbound;
using namespace setbound_bench;
using Clock = std::chrono::steady_clock;

namespace {

// One estimator ready to run: reset() goes back to the initial set, step(k) uses row k.
struct Runnable {
  std::function<void()> reset;
  std::function<void(Index)> step;
};

using Builder = std::function<Runnable(const Benchmark&)>;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

ZonotopeReduction reduction_of(const std::string& cora) {
  if (cora.rfind("pca", 0) == 0) return ZonotopeReduction::Pca;
  return ZonotopeReduction::Girard;  // CORA's default (spec §1.1), as CoraBenchmark.reduction_method
}

Index max_generators(const Benchmark& b) {
  const Index n = b.system->nx();
  return std::max<Index>(static_cast<Index>(b.order * static_cast<double>(n) + 1e-9), n);
}

Zonotope initial_set(const Benchmark& b) { return Zonotope(b.p0, b.H0); }

// Non-zero-width columns of W and V as thesis::Plant wants them (a zero column when empty, as
// the Python runners do).
MatrixXd or_zero_column(const MatrixXd& G, Index rows) { return G.cols() ? G : MatrixXd::Zero(rows, 1); }

thesis::Plant plant_of(const Benchmark& b) {
  const LinearSystem& s = *b.system;
  return thesis::Plant(s.A(), s.B(), s.C(), or_zero_column(b.Wg, s.nx()), or_zero_column(b.Vg, s.ny()));
}

void require_no_output_offset(const Benchmark& b, const char* what) {
  if (b.system->D().cwiseAbs().maxCoeff() != 0.0)
    throw std::runtime_error(std::string("model: an output offset (D u) is not supported by ") + what);
}

Runnable zonotopic_observer(const Benchmark& b, ZonotopicRule rule, const MatrixXd& gain = MatrixXd()) {
  ZonotopicObserverOptions opt;
  opt.rule = rule;
  opt.gain = gain;
  opt.max_generators = max_generators(b);
  opt.reduction = reduction_of(b.reduction);
  opt.convention = Convention::Setbound;
  auto obs = std::make_shared<ZonotopicObserver>(*b.system, initial_set(b), opt);
  return {[obs] { obs->reset(); },
          [obs, &b](Index k) { obs->update(b.Y.row(k).transpose(), b.U.row(k).transpose()); }};
}

struct Method {
  std::string name;
  std::function<Runnable(const Benchmark&, double& design_seconds)> build;
};

std::vector<Method> methods() {
  std::vector<Method> m;
  auto timed = [](double& t, auto&& f) {
    const auto t0 = Clock::now();
    auto r = f();
    t = seconds_since(t0);
    return r;
  };
  m.push_back({"FRad-A", [](const Benchmark& b, double&) { return zonotopic_observer(b, ZonotopicRule::SegmentMin); }});
  m.push_back({"VolMin-A", [](const Benchmark& b, double&) { return zonotopic_observer(b, ZonotopicRule::VolumeMin); }});
  m.push_back({"VolMin-B", [](const Benchmark& b, double&) { return zonotopic_observer(b, ZonotopicRule::Bravo); }});
  m.push_back({"FRad-B", [](const Benchmark& b, double&) { return zonotopic_observer(b, ZonotopicRule::Wang); }});
  m.push_back({"FRad-C", [](const Benchmark& b, double&) { return zonotopic_observer(b, ZonotopicRule::Combastel); }});
  const std::pair<const char*, std::pair<ZonotopicGainMethod, ZonotopicRule>> designed[] = {
      {"PRad-A", {ZonotopicGainMethod::PRadA, ZonotopicRule::FixedStrips}},
      {"PRad-B", {ZonotopicGainMethod::PRadB, ZonotopicRule::FixedLambda}},
      {"PRad-C", {ZonotopicGainMethod::PRadC, ZonotopicRule::FixedLambda}},
      {"PRad-D", {ZonotopicGainMethod::PRadD, ZonotopicRule::FixedLambda}},
      {"PRad-E", {ZonotopicGainMethod::PRadE, ZonotopicRule::FixedGain}},
      {"Nom-G", {ZonotopicGainMethod::NomG, ZonotopicRule::FixedGain}}};
  for (const auto& [name, how] : designed) {
    const auto [design, rule] = how;
    m.push_back({name, [timed, design, rule](const Benchmark& b, double& t) {
                   const MatrixXd L = timed(t, [&] { return design_zonotopic_gain(*b.system, design).gain; });
                   return zonotopic_observer(b, rule, L);
                 }});
  }
  m.push_back({"Hinf-G", [timed](const Benchmark& b, double& t) {
                 require_no_output_offset(b, "the interval observer");
                 const thesis::Plant plant = plant_of(b);
                 const MatrixXd L = timed(t, [&] { return thesis::hinf_observer_gain(plant).L; });
                 const Zonotope z = initial_set(b);
                 const VectorXd r = b.H0.cwiseAbs().rowwise().sum();
                 const Box x0(b.p0 - r, b.p0 + r, "x0");
                 const Index nd = plant.nd(), nv = plant.nv();
                 auto obs = std::make_shared<thesis::IntervalLuenbergerObserver>(
                     plant, L, x0, b.p0, Box(-VectorXd::Ones(nd), VectorXd::Ones(nd), "d"),
                     Box(-VectorXd::Ones(nv), VectorXd::Ones(nv), "v"));
                 const auto initial = std::make_shared<thesis::IntervalLuenbergerObserver>(*obs);
                 return Runnable{[obs, initial] { *obs = *initial; },
                                 [obs, &b](Index k) { obs->step(b.Y.row(k).transpose(), b.U.row(k).transpose()); }};
               }});
  for (const auto& [name, rule] : {std::pair{"ESO-A", BoundingRule::Gollamudi}, std::pair{"ESO-B", BoundingRule::Liu}})
    m.push_back({name, [rule = rule](const Benchmark& b, double&) {
                   BoundingEllipsoidOptions opt;
                   opt.rule = rule;
                   opt.convention = Convention::Setbound;
                   auto shape = [](const MatrixXd& G, Index n) {
                     return G.cols() ? enclosing_ellipsoid_shape(G) : MatrixXd(MatrixXd::Zero(n, n));
                   };
                   const Index n = b.system->nx(), p = b.system->ny();
                   auto est = std::make_shared<BoundingEllipsoidEstimator>(
                       *b.system, shape(b.Wg, n), shape(b.Vg, p), b.p0, shape(b.H0, n), 1.0, opt);
                   return Runnable{[est] { est->reset(); },
                                   [est, &b](Index k) { est->step(b.Y.row(k).transpose(), b.U.row(k).transpose()); }};
                 }});
  // ESO-C and ESO-D: the thesis's ellipsoidal set-membership observer, two offline designs.
  for (const char* name : {"ESO-C", "ESO-D"})
    m.push_back({name, [timed, name](const Benchmark& b, double& t) {
                   require_no_output_offset(b, name);
                   const thesis::Plant plant = plant_of(b);
                   const VectorXd wbar = VectorXd::Ones(plant.nd() + plant.nv());
                   const thesis::EllipsoidalSMDesign d = timed(t, [&] {
                     return std::string(name) == "ESO-C" ? thesis::design_ellipsoidal_sm_observer(plant, wbar)
                                                         : thesis::design_eso_d(plant, wbar).sm;
                   });
                   const VectorXd r = b.H0.cwiseAbs().rowwise().sum();
                   const double mu0 = thesis::hinf_detail::mu_from_box(d, b.p0 - r, b.p0 + r, b.p0);
                   auto obs = std::make_shared<thesis::EllipsoidalSMObserver>(plant, d, b.p0, mu0);
                   return Runnable{[obs, &b, mu0] { obs->reset(b.p0, mu0); },
                                   [obs, &b](Index k) { obs->step(b.Y.row(k).transpose(), b.U.row(k).transpose()); }};
                 }});
  for (const auto& [name, corr] :
       {std::pair{"CZN-A", CZCorrection::ExactOutput}, std::pair{"CZN-B", CZCorrection::WangStrips}})
    m.push_back({name, [corr = corr](const Benchmark& b, double&) {
                   CZOptions opt;
                   opt.correction = corr;
                   auto est = std::make_shared<ConstrainedZonotopicEstimator>(
                       *b.system, ConstrainedZonotope(initial_set(b)), opt);
                   return Runnable{[est] { est->reset(); },
                                   [est, &b](Index k) { est->update(b.Y.row(k).transpose(), b.U.row(k).transpose()); }};
                 }});
  m.push_back({"ROPO", [](const Benchmark& b, double&) {
                 ParallelotopeOptions opt;
                 opt.reduction = reduction_of(b.reduction);
                 auto est = std::make_shared<ParallelotopeEstimator>(*b.system, initial_set(b), opt);
                 return Runnable{[est] { est->reset(); },
                                 [est, &b](Index k) { est->update(b.Y.row(k).transpose(), b.U.row(k).transpose()); }};
               }});
  return m;
}

struct Row {
  std::string model, alg, error;
  Index n = 0;
  std::size_t steps = 0, horizons = 0;
  Index horizon = 0;
  double median_us = NAN, p90_us = NAN, design_ms = NAN;
};

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    if (c == '\n') { out += "\\n"; continue; }
    out += c;
  }
  return out + "\"";
}

std::string json_number(double v) {
  if (!std::isfinite(v)) return "null";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

bool wanted(const std::vector<std::string>& list, const std::string& name) {
  return list.empty() || std::find(list.begin(), list.end(), name) != list.end();
}

}  // namespace

int main(int argc, char** argv) {
  std::string dir;
  if (const char* env = std::getenv("SETBOUND_CORA_DATA")) dir = env;
#ifdef SETBOUND_CORA_DATA_DEFAULT
  if (dir.empty()) dir = SETBOUND_CORA_DATA_DEFAULT;
#endif
  std::size_t min_steps = 400;
  double max_seconds = 20;
  std::string out_file;
  std::vector<std::string> models = {"alamo2005_2d_cora_unittest", "vehicle2_cora_unittest", "pedestrian4", "vehicle6",
                                     "tank30"},
                           only;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--min-steps" && i + 1 < argc) min_steps = static_cast<std::size_t>(std::stoul(argv[++i]));
    else if (a == "--max-seconds" && i + 1 < argc) max_seconds = std::stod(argv[++i]);
    else if (a == "--models" && i + 1 < argc) models = split(argv[++i]);
    else if (a == "--methods" && i + 1 < argc) only = split(argv[++i]);
    else if (a == "--json" && i + 1 < argc) out_file = argv[++i];
    else if (!a.empty() && a[0] == '-') {
      std::fprintf(stderr, "bench_cora_cpp: unknown option %s\n", a.c_str());
      return 2;
    } else dir = a;
  }
  if (dir.empty()) {
    std::fprintf(stderr, "usage: bench_cora_cpp DATA_DIR [--models a,b] [--methods A,B] [--min-steps N] "
                         "[--max-seconds S] [--json FILE]\n");
    return 2;
  }
  std::string loadavg = "unknown";
  if (std::ifstream la("/proc/loadavg"); la) {
    std::string a, b, c;
    la >> a >> b >> c;
    loadavg = a + " " + b + " " + c;
  }
  std::vector<Row> rows;
  const std::vector<Method> all = methods();
  for (const std::string& name : models) {
    const Benchmark b = load(dir + "/" + name + ".json", name);
    const Index N = b.Y.rows();
    for (const Method& m : all) {
      if (!wanted(only, m.name)) continue;
      Row r{name, m.name, "", b.system->nx()};
      r.horizon = N;
      try {
        double design = 0;
        Runnable run = m.build(b, design);
        r.design_ms = design * 1e3;
        std::vector<double> times;
        const auto start = Clock::now();
        do {
          run.reset();
          for (Index k = 0; k < N; ++k) {
            const auto t0 = Clock::now();
            run.step(k);
            times.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
            // A slow method (LPs per step) stops within the horizon: the median is then over the
            // first steps only, which the row says (steps_timed < the horizon).
            if (seconds_since(start) > max_seconds) break;
          }
          ++r.horizons;
        } while (times.size() < min_steps && seconds_since(start) < max_seconds);
        r.steps = times.size();
        r.median_us = percentile(times, 0.5);
        r.p90_us = percentile(times, 0.9);
      } catch (const std::exception& e) {
        r.error = e.what();
      }
      std::fprintf(stderr, "%-28s %-9s %10.2f µs/step  design %8.2f ms  %s\n", name.c_str(), m.name.c_str(),
                   r.median_us, r.design_ms, r.error.c_str());
      rows.push_back(r);
    }
  }
  std::string loadavg_end = "unknown";
  if (std::ifstream la("/proc/loadavg"); la) {
    std::string a, b, c;
    la >> a >> b >> c;
    loadavg_end = a + " " + b + " " + c;
  }
#if defined(__AVX512F__)
  const char* simd = "AVX-512";
#elif defined(__AVX2__)
  const char* simd = "AVX2";
#elif defined(__AVX__)
  const char* simd = "AVX";
#else
  const char* simd = "SSE2";
#endif
  char when[64];
  const std::time_t now = std::time(nullptr);
  std::strftime(when, sizeof when, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
  std::ostringstream out;
  out << "{\"program\": \"bench_cora_cpp\", \"date\": " << json_string(when)
      << ", \"hardware_threads\": " << std::thread::hardware_concurrency() << ", \"simd\": " << json_string(simd)
      << ", \"loadavg_start\": " << json_string(loadavg) << ", \"loadavg_end\": " << json_string(loadavg_end)
      << ", \"min_steps\": " << min_steps << ", \"max_seconds\": " << json_number(max_seconds) << ",\n \"rows\": [";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Row& r = rows[i];
    out << (i ? ",\n  " : "\n  ") << "{\"model\": " << json_string(r.model) << ", \"alg\": " << json_string(r.alg)
        << ", \"n\": " << r.n << ", \"horizon\": " << r.horizon << ", \"steps_timed\": " << r.steps << ", \"median_us\": " << json_number(r.median_us)
        << ", \"p90_us\": " << json_number(r.p90_us) << ", \"design_ms\": " << json_number(r.design_ms)
        << ", \"error\": " << (r.error.empty() ? "null" : json_string(r.error)) << "}";
  }
  out << "\n]}\n";
  if (out_file.empty()) {
    std::printf("%s", out.str().c_str());
  } else {
    std::ofstream(out_file) << out.str();
  }
  return 0;
}
