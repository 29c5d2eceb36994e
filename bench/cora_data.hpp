// setbound — CORA's linearSysDT observer benchmark files (shared/benchmarks/cora_linearSysDT_observe)
// read into setbound's form for the C++ bench programs, as python/setbound/benchmarks.py does:
// E = [G_W, 0], F = [0, G_V], the constants c + c_W and c_V as one extra input column whose input
// is always 1; rows of Y/U are time steps. A minimal JSON reader (objects, arrays, numbers,
// strings, literals) keeps the programs free of a JSON dependency.
#pragma once

#include <Eigen/Core>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "setbound/core/linear_system.hpp"

namespace setbound_bench {

using setbound::LinearSystem;
using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

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
inline void flatten(const Json& j, std::vector<double>& out, std::vector<Index>& shape, std::size_t depth = 0) {
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
inline MatrixXd matrix(const Json& j, Index rows) {
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

inline Index outer_size(const Json& j) { return j.kind == Json::Array ? static_cast<Index>(j.items.size()) : 1; }

// ---- CORA benchmark in setbound's form (as python/setbound/benchmarks.py) -------------------
struct Benchmark {
  std::string name;
  std::unique_ptr<LinearSystem> system;
  VectorXd p0;
  MatrixXd H0, Y, U;  // Y: N × n_y, U: N × (n_u + 1), the constant input last
  double order = 20;
  std::string reduction;
  std::map<std::string, std::pair<VectorXd, VectorXd>> golden;
  MatrixXd Wg, Vg;  // CORA's W and V generators (E = [Wg, 0], F = [0, Vg])
  MatrixXd truth;   // N × n_x when the file has a true trajectory (3 decimals), else empty
};

inline Benchmark load(const std::string& path, const std::string& name) {
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
  b.Wg = Wg;
  b.Vg = Vg;
  const MatrixXd u = matrix(d["u"], nu);
  const MatrixXd y = matrix(d["y"], ny);
  b.Y = y.transpose();
  b.U.resize(u.cols(), nu + 1);
  b.U << u.transpose(), VectorXd::Ones(u.cols());
  b.p0 = matrix(d["R0"]["center"], n).col(0);
  b.H0 = matrix(d["R0"]["generators"], n);
  if (d.has("traj_x")) {
    const Json& tx = d["traj_x"];  // rows are time steps (as setbound.benchmarks.load_cora reads it)
    b.truth = matrix(tx, outer_size(tx));
  }
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


}  // namespace setbound_bench
