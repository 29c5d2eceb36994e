// setbound — per-step time of the zonotopic estimators in C++ on CORA's linearSysDT observer
// data (shared/benchmarks/cora_linearSysDT_observe), with CORA's settings (zonotope order ×
// n_x generators, CORA's reduction technique). Built only with -DSETBOUND_BUILD_BENCH=ON.
//
//   bench_zonotopic_cpp [DATA_DIR] [--min-steps N] [--only NAME] [--update-doc docs/benchmarks.md]
//
// For every data set and method it runs the whole horizon repeatedly (at least N timed steps
// in all, default 400), times every step with a steady clock and prints the median, the
// 90th percentile and the median over the steps where the generator limit is reached
// ("full"), plus the final interval hull's largest difference to CORA's saved one. With
// --update-doc the table replaces the block between the bench markers in that file.
#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "setbound/core/linear_system.hpp"
#include "setbound/estimators/pradius.hpp"
#include "setbound/estimators/zonotopic.hpp"

using namespace setbound;
using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

// ---- a minimal JSON reader (objects, arrays, numbers, strings, literals) ------------------
struct Json {
  enum Kind { Null, Bool, Number, String, Array, Object } kind = Null;
  double number = 0;
  std::string text;
  std::vector<Json> items;
  std::map<std::string, Json> fields;

  const Json& operator[](const std::string& key) const {
    auto it = fields.find(key);
    if (it == fields.end()) throw std::runtime_error("json: missing key " + key);
    return it->second;
  }
  bool has(const std::string& key) const { return fields.count(key) != 0; }
};

class JsonParser {
 public:
  explicit JsonParser(const std::string& s) : s_(s) {}
  Json parse() {
    Json v = value();
    ws();
    if (i_ != s_.size()) fail("trailing characters");
    return v;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error("json: " + what + " at offset " + std::to_string(i_));
  }
  void ws() {
    while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_]))) ++i_;
  }
  Json value() {
    ws();
    if (i_ >= s_.size()) fail("unexpected end");
    Json v;
    const char ch = s_[i_];
    if (ch == '{') {
      v.kind = Json::Object;
      ++i_;
      ws();
      if (s_[i_] == '}') return ++i_, v;
      for (;;) {
        ws();
        const std::string key = string();
        ws();
        if (s_[i_++] != ':') fail("expected ':'");
        v.fields[key] = value();
        ws();
        if (s_[i_] == ',') { ++i_; continue; }
        if (s_[i_++] != '}') fail("expected '}'");
        return v;
      }
    }
    if (ch == '[') {
      v.kind = Json::Array;
      ++i_;
      ws();
      if (s_[i_] == ']') return ++i_, v;
      for (;;) {
        v.items.push_back(value());
        ws();
        if (s_[i_] == ',') { ++i_; continue; }
        if (s_[i_++] != ']') fail("expected ']'");
        return v;
      }
    }
    if (ch == '"') {
      v.kind = Json::String;
      v.text = string();
      return v;
    }
    if (s_.compare(i_, 4, "true") == 0) return i_ += 4, v.kind = Json::Bool, v.number = 1, v;
    if (s_.compare(i_, 5, "false") == 0) return i_ += 5, v.kind = Json::Bool, v;
    if (s_.compare(i_, 4, "null") == 0) return i_ += 4, v;
    if (s_.compare(i_, 3, "NaN") == 0) return i_ += 3, v.kind = Json::Number, v.number = NAN, v;
    const char* begin = s_.c_str() + i_;
    char* end = nullptr;
    v.number = std::strtod(begin, &end);
    if (end == begin) fail("unexpected character");
    i_ += static_cast<std::size_t>(end - begin);
    v.kind = Json::Number;
    return v;
  }
  std::string string() {
    if (s_[i_] != '"') fail("expected a string");
    std::string out;
    for (++i_; i_ < s_.size() && s_[i_] != '"'; ++i_) {
      if (s_[i_] == '\\') ++i_;  // escapes are kept verbatim (only keys and notes are strings)
      out.push_back(s_[i_]);
    }
    ++i_;
    return out;
  }
  const std::string& s_;
  std::size_t i_ = 0;
};

// Numbers of a (nested) array, row-major; rows/cols describe the nesting (a scalar is 1×1).
void flatten(const Json& j, std::vector<double>& out, std::vector<Index>& shape, std::size_t depth = 0) {
  if (j.kind == Json::Number) {
    out.push_back(j.number);
    return;
  }
  if (j.kind != Json::Array) throw std::runtime_error("json: expected numbers");
  if (shape.size() <= depth) shape.push_back(static_cast<Index>(j.items.size()));
  for (const Json& x : j.items) flatten(x, out, shape, depth + 1);
}

// A matrix with `rows` rows from a (nested) array, read row-major: an n×k nested array, a flat
// list of n numbers (one column) or an n×1 nested column.
MatrixXd matrix(const Json& j, Index rows) {
  std::vector<double> v;
  std::vector<Index> shape;
  flatten(j, v, shape);
  const Index total = static_cast<Index>(v.size());
  if (rows <= 0 || total % rows != 0) throw std::runtime_error("json: cannot reshape array");
  const Index cols = total / rows;
  MatrixXd M(rows, cols);
  for (Index i = 0; i < rows; ++i)
    for (Index k = 0; k < cols; ++k) M(i, k) = v[static_cast<std::size_t>(i * cols + k)];
  return M;
}

Index outer_size(const Json& j) { return j.kind == Json::Array ? static_cast<Index>(j.items.size()) : 1; }

// ---- CORA benchmark in setbound's form (as python/setbound/benchmarks.py) -------------------
struct Benchmark {
  std::string name;
  std::unique_ptr<LinearSystem> system;
  VectorXd p0;
  MatrixXd H0, Y, U;  // Y: N × n_y, U: N × (n_u + 1), the constant input last
  double order = 20;
  std::string reduction;
  std::map<std::string, std::pair<VectorXd, VectorXd>> golden;
};

Benchmark load(const std::string& path, const std::string& name) {
  std::ifstream f(path);
  if (!f) throw std::runtime_error("cannot open " + path);
  std::stringstream ss;
  ss << f.rdbuf();
  const std::string text = ss.str();
  const Json d = JsonParser(text).parse();
  Benchmark b;
  b.name = name;
  const Index n = outer_size(d["A"]);
  const MatrixXd A = matrix(d["A"], n);
  const Json& Cj = d["C"];
  const Index ny = Cj.kind == Json::Array && !Cj.items.empty() && Cj.items[0].kind == Json::Array ? outer_size(Cj) : 1;
  const MatrixXd C = matrix(Cj, ny);
  const MatrixXd B = matrix(d["B"], n);
  const VectorXd c = d.has("c") ? VectorXd(matrix(d["c"], n).col(0)) : VectorXd::Zero(n);
  const VectorXd Wc = matrix(d["W"]["center"], n).col(0);
  const MatrixXd Wg = matrix(d["W"]["generators"], n);
  const VectorXd Vc = matrix(d["V"]["center"], ny).col(0);
  const MatrixXd Vg = matrix(d["V"]["generators"], ny);
  const MatrixXd D = d.has("D") ? matrix(d["D"], ny) : MatrixXd::Zero(ny, B.cols());
  const Index nw = Wg.cols(), nv = Vg.cols(), nu = B.cols();
  MatrixXd E = MatrixXd::Zero(n, nw + nv), F = MatrixXd::Zero(ny, nw + nv);
  E.leftCols(nw) = Wg;
  F.rightCols(nv) = Vg;
  MatrixXd Bx(n, nu + 1), Dx(ny, nu + 1);
  Bx << B, c + Wc;
  Dx << D, Vc;
  b.system = std::make_unique<LinearSystem>(A, C, E, F, Bx, Dx);
  const MatrixXd u = matrix(d["u"], nu);
  const MatrixXd y = matrix(d["y"], ny);
  b.Y = y.transpose();
  b.U.resize(u.cols(), nu + 1);
  b.U << u.transpose(), VectorXd::Ones(u.cols());
  b.p0 = matrix(d["R0"]["center"], n).col(0);
  b.H0 = matrix(d["R0"]["generators"], n);
  b.order = d.has("zonotopeOrder") ? d["zonotopeOrder"].number : 20.0;
  b.reduction = d.has("reductionTechnique") ? d["reductionTechnique"].text : "girard";
  if (d.has("golden_final_interval_hull")) {
    for (const auto& [key, v] : d["golden_final_interval_hull"]["values"].fields) {
      if (v.kind == Json::Object) {
        b.golden[key] = {matrix(v["lower"], n).col(0), matrix(v["upper"], n).col(0)};
      } else {
        const MatrixXd lu = matrix(v, 2);  // [lower; upper]
        b.golden[key] = {lu.row(0).transpose(), lu.row(1).transpose()};
      }
    }
  }
  return b;
}

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return NAN;
  const std::size_t k = static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5);
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

struct Row {
  std::string data, method, reduction;
  Index n, limit;
  std::size_t steps;
  double median_us, p90_us, full_us, diff, box = 0;
  std::string golden_key;
};

ZonotopeReduction reduction_of(const std::string& cora) {
  if (cora.rfind("pca", 0) == 0) return ZonotopeReduction::Pca;
  if (cora.rfind("girard", 0) == 0) return ZonotopeReduction::Girard;
  return ZonotopeReduction::Combastel;
}

const char* reduction_name(ZonotopeReduction r) {
  switch (r) {
    case ZonotopeReduction::Pca: return "pca";
    case ZonotopeReduction::Girard: return "girard";
    default: return "combastel";
  }
}

Row run(const Benchmark& b, const std::string& method, const ZonotopeGain& gain, ZonotopeReduction red,
        std::size_t min_steps, const std::string& golden_key, Index horizon = -1,
        const std::vector<Index>& strip_order = {}) {
  const Index n = b.system->nx();
  ZonotopicOptions opt;
  opt.strip_order = strip_order;
  opt.max_generators = std::max<Index>(static_cast<Index>(b.order * static_cast<double>(n) + 1e-9), n);
  opt.reduction = red;
  const Index N = horizon > 0 ? std::min<Index>(horizon, b.Y.rows()) : b.Y.rows();
  std::vector<double> times, full;
  VectorXd lo, hi;
  double box = 0;
  const auto total_start = std::chrono::steady_clock::now();
  do {
    ZonotopicEstimator est(*b.system, Zonotope(b.p0, b.H0), gain, opt);
    for (Index k = 0; k < N; ++k) {
      const auto t0 = std::chrono::steady_clock::now();
      est.update(b.Y.row(k).transpose(), b.U.row(k).transpose());
      const auto t1 = std::chrono::steady_clock::now();
      const double us = std::chrono::duration<double, std::micro>(t1 - t0).count();
      times.push_back(us);
      if (est.reduced_last_step()) full.push_back(us);
      box = std::max(box, est.current_box().maxCoeff() / (est.current_upper() - est.current_lower()).maxCoeff() * 2);
    }
    lo = est.current_lower();
    hi = est.current_upper();
  } while (times.size() < min_steps &&
           std::chrono::steady_clock::now() - total_start < std::chrono::seconds(60));
  Row r{b.name, method, reduction_name(red), n, opt.max_generators, times.size(),
        percentile(times, 0.5), percentile(times, 0.9), percentile(full, 0.5), NAN, 0.0, golden_key};
  auto it = b.golden.find(golden_key);
  r.box = box;
  if (it != b.golden.end())
    r.diff = std::max((lo - it->second.first).cwiseAbs().maxCoeff(), (hi - it->second.second).cwiseAbs().maxCoeff());
  return r;
}

std::string fmt(double v, const char* f) {
  if (std::isnan(v)) return "—";
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

}  // namespace

int main(int argc, char** argv) {
  std::string dir;
  if (const char* env = std::getenv("SETBOUND_CORA_DATA")) dir = env;
#ifdef SETBOUND_CORA_DATA_DEFAULT
  if (dir.empty()) dir = SETBOUND_CORA_DATA_DEFAULT;
#endif
  std::size_t min_steps = 400;
  std::string doc, only;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--min-steps" && i + 1 < argc) min_steps = static_cast<std::size_t>(std::stoul(argv[++i]));
    else if (a == "--only" && i + 1 < argc) only = argv[++i];
    else if (a == "--update-doc" && i + 1 < argc) doc = argv[++i];
    else dir = a;
  }
  if (dir.empty()) {
    std::fprintf(stderr, "usage: bench_zonotopic_cpp DATA_DIR [--min-steps N] [--only NAME] [--update-doc FILE]\n");
    return 2;
  }
  std::vector<Row> rows;
  const ZonotopeGain seg(segment_min_gain);
  for (const char* name : {"alamo2005_2d_cora_unittest", "vehicle2_cora_unittest", "pedestrian4", "vehicle6", "tank30"}) {
    if (!only.empty() && only != name) continue;
    const Benchmark b = load(dir + "/" + name + ".json", name);
    const ZonotopeReduction cora_red = reduction_of(b.reduction);
    const std::string key = b.golden.count("FRad-A") ? "FRad-A" : (b.golden.count("FRad-A [else]") ? "FRad-A [else]" : "");
    rows.push_back(run(b, "segment min. (FRad-A)", seg, cora_red, min_steps, key));
    if (cora_red != ZonotopeReduction::Combastel)
      rows.push_back(run(b, "segment min. (FRad-A)", seg, ZonotopeReduction::Combastel, min_steps, key));
    if (std::string(name) == "tank30")
      rows.push_back(run(b, "segment min., 20 steps", seg, cora_red, min_steps, "FRad-A [tFinal==10]", 20));
    // The P-radius estimator ([Le2013], papers.md §3.2): offline gains, the fixed-gain path of the same step.
    if (std::string(name) == "alamo2005_2d_cora_unittest" || std::string(name) == "vehicle6") {
      try {
        const PRadiusDesign d = design_pradius(*b.system);
        rows.push_back(run(b, "P-radius (approach 1)", pradius_gain(d), cora_red, min_steps, "", -1, d.strip_order));
      } catch (const std::exception& e) {
        std::fprintf(stderr, "%s: P-radius design failed: %s\n", name, e.what());
      }
    }
  }
  std::string loadavg = "unknown";
  if (std::ifstream la("/proc/loadavg"); la) {
    std::string a, b, c;
    la >> a >> b >> c;
    loadavg = a + " " + b + " " + c;
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
  std::ostringstream out;
  char when[64];
  const std::time_t now = std::time(nullptr);
  std::strftime(when, sizeof when, "%Y-%m-%d", std::localtime(&now));
  out << "Generated by `bench/bench_zonotopic_cpp` on " << when << ", " << std::thread::hardware_concurrency()
      << " hardware threads, load average " << loadavg << " at the start, vectorised for " << simd
      << "; one `update()` per step timed with a steady clock, median over at least "
      << min_steps << " steps (whole horizons repeated). \"full\": median over the steps that ran the "
      << "reduction (the generator limit reached). \"box\": largest pending rounding box over the run, "
      << "relative to the largest radius of the set.\n\n"
      << "| data | n_x | method | reduction | limit | steps timed | median µs/step | p90 µs | full µs | "
         "final hull vs CORA | box |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const Row& r : rows)
    out << "| " << r.data << " | " << r.n << " | " << r.method << " | " << r.reduction << " | " << r.limit << " | "
        << r.steps << " | " << fmt(r.median_us, "%.2f") << " | " << fmt(r.p90_us, "%.2f") << " | "
        << fmt(r.full_us, "%.2f") << " | " << fmt(r.diff, "%.1e") << " | " << fmt(r.box, "%.0e") << " |\n";
  std::printf("%s", out.str().c_str());
  if (!doc.empty()) {
    std::ifstream in(doc);
    std::stringstream ss;
    ss << in.rdbuf();
    std::string text = ss.str();
    const std::string begin = "<!-- bench_zonotopic_cpp:begin -->", end = "<!-- bench_zonotopic_cpp:end -->";
    const std::string block = begin + "\n" + out.str() + end;
    const auto a = text.find(begin), e = text.find(end);
    if (a != std::string::npos && e != std::string::npos) text.replace(a, e + end.size() - a, block);
    else text += "\n## C++ per-step times\n\n" + block + "\n";
    std::ofstream(doc) << text;
  }
  return 0;
}
