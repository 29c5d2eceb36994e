// setbound — C ABI: intervals, boxes and interval matrices (setbound.h section "intervals").
//
// Arrays of intervals cross as separate lo/hi arrays; each entry is validated (NaN, lo > hi)
// with a message that names the argument and the entry. All arithmetic is the guaranteed
// interval arithmetic of sets/interval.hpp.
#include <string>
#include <vector>

#include "c_api_common.hpp"
#include "setbound/sets/box.hpp"
#include "setbound/sets/interval.hpp"
#include "setbound/sets/interval_matrix.hpp"

namespace setbound::capi {
namespace {

/// n intervals from lo/hi arrays; the empty encoding (+inf, -inf) is allowed.
std::vector<Interval> interval_array(const double* lo, const double* hi, int n,
                                     const char* name) {
  require_dimension(n, name, true);
  std::vector<Interval> out;
  if (n == 0) return out;
  require_pointer(lo, (std::string(name) + " (lower ends)").c_str());
  require_pointer(hi, (std::string(name) + " (upper ends)").c_str());
  out.reserve(std::size_t(n));
  for (int i = 0; i < n; ++i) {
    Interval::validate(lo[i], hi[i], std::string(name) + " entry " + std::to_string(i));
    out.push_back(Interval::unchecked(lo[i], hi[i]));
  }
  return out;
}

void require_outputs(const double* lo, const double* hi, int n) {
  if (n == 0) return;
  require_pointer(lo, "lo");
  require_pointer(hi, "hi");
}

void write(const std::vector<Interval>& v, double* lo, double* hi) {
  for (std::size_t i = 0; i < v.size(); ++i) {
    lo[i] = v[i].lo();
    hi[i] = v[i].hi();
  }
}

void write(const Box& b, double* lo, double* hi) {
  for (Eigen::Index i = 0; i < b.size(); ++i) {
    lo[i] = b.lo()(i);
    hi[i] = b.hi()(i);
  }
}

IntervalMatrix imatrix_arg(const double* lo, const double* hi, int rows, int cols,
                           const char* name) {
  const std::string n(name);
  const Eigen::MatrixXd L = matrix_arg(lo, rows, cols, (n + " (lower bound)").c_str());
  const Eigen::MatrixXd H = matrix_arg(hi, rows, cols, (n + " (upper bound)").c_str());
  return IntervalMatrix(L, H, n);
}

void unknown_op(int op) {
  throw InvalidArgumentError("op: unknown operation code " + std::to_string(op));
}

}  // namespace
}  // namespace setbound::capi

using namespace setbound;
using namespace setbound::capi;

extern "C" {

int sb_interval_binary(int op, int n, const double* alo, const double* ahi, const double* blo,
                       const double* bhi, double* lo, double* hi) {
  return guard("sb_interval_binary", [&] {
    if (op < SB_IV_ADD || op > SB_IV_HULL) unknown_op(op);
    const auto a = interval_array(alo, ahi, n, "a");
    const auto b = interval_array(blo, bhi, n, "b");
    require_outputs(lo, hi, n);
    std::vector<Interval> out(static_cast<std::size_t>(n));
    for (std::size_t i = 0; i < out.size(); ++i) {
      switch (op) {
        case SB_IV_ADD: out[i] = a[i] + b[i]; break;
        case SB_IV_SUB: out[i] = a[i] - b[i]; break;
        case SB_IV_MUL: out[i] = a[i] * b[i]; break;
        case SB_IV_DIV: out[i] = a[i] / b[i]; break;
        case SB_IV_INTERSECT: out[i] = a[i].intersect(b[i]); break;
        case SB_IV_HULL: out[i] = a[i].hull(b[i]); break;
        default: unknown_op(op);
      }
    }
    write(out, lo, hi);
  });
}

int sb_interval_unary(int op, int n, const double* xlo, const double* xhi, double* lo,
                      double* hi) {
  return guard("sb_interval_unary", [&] {
    if (op < SB_IV_NEG || op > SB_IV_ABS) unknown_op(op);
    const auto x = interval_array(xlo, xhi, n, "x");
    require_outputs(lo, hi, n);
    std::vector<Interval> out(static_cast<std::size_t>(n));
    for (std::size_t i = 0; i < out.size(); ++i) {
      switch (op) {
        case SB_IV_NEG: out[i] = -x[i]; break;
        case SB_IV_RECIP: out[i] = ia::reciprocal(x[i]); break;
        case SB_IV_SQR: out[i] = ia::sqr(x[i]); break;
        case SB_IV_SQRT: out[i] = ia::sqrt(x[i]); break;
        case SB_IV_EXP: out[i] = ia::exp(x[i]); break;
        case SB_IV_SIN: out[i] = ia::sin(x[i]); break;
        case SB_IV_COS: out[i] = ia::cos(x[i]); break;
        case SB_IV_ABS: out[i] = ia::abs(x[i]); break;
        default: unknown_op(op);
      }
    }
    write(out, lo, hi);
  });
}

int sb_interval_pow(int n, const double* xlo, const double* xhi, int p, double* lo, double* hi) {
  return guard("sb_interval_pow", [&] {
    const auto x = interval_array(xlo, xhi, n, "x");
    require_outputs(lo, hi, n);
    std::vector<Interval> out;
    out.reserve(x.size());
    for (const Interval& xi : x) out.push_back(ia::pow(xi, p));
    write(out, lo, hi);
  });
}

int sb_box_volume(int n, const double* lo, const double* hi, double* volume) {
  return guard("sb_box_volume", [&] {
    const Box b = box_arg(lo, hi, n, "box");
    require_pointer(volume, "volume");
    *volume = b.volume();
  });
}

int sb_matrix_mul_box(int rows, int cols, const double* M, const double* xlo, const double* xhi,
                      double* ylo, double* yhi) {
  return guard("sb_matrix_mul_box", [&] {
    const Eigen::MatrixXd m = matrix_arg(M, rows, cols, "M");
    const Box x = box_arg(xlo, xhi, cols, "x");
    require_outputs(ylo, yhi, rows);
    write(multiply(m, x, "M"), ylo, yhi);
  });
}

int sb_imatrix_mul_box(int rows, int cols, const double* Mlo, const double* Mhi,
                       const double* xlo, const double* xhi, double* ylo, double* yhi) {
  return guard("sb_imatrix_mul_box", [&] {
    const IntervalMatrix m = imatrix_arg(Mlo, Mhi, rows, cols, "M");
    const Box x = box_arg(xlo, xhi, cols, "x");
    require_outputs(ylo, yhi, rows);
    write(m * x, ylo, yhi);
  });
}

int sb_imatrix_mul_matrix(int rows, int inner, int cols, const double* Mlo, const double* Mhi,
                          const double* N, double* Rlo, double* Rhi) {
  return guard("sb_imatrix_mul_matrix", [&] {
    const IntervalMatrix m = imatrix_arg(Mlo, Mhi, rows, inner, "M");
    const Eigen::MatrixXd n = matrix_arg(N, inner, cols, "N");
    require_dimension(cols, "N", true);
    if (rows > 0 && cols > 0) {
      require_pointer(Rlo, "Rlo");
      require_pointer(Rhi, "Rhi");
    }
    const IntervalMatrix r = m * n;
    RowMap(Rlo, rows, cols) = r.lo();
    RowMap(Rhi, rows, cols) = r.hi();
  });
}

int sb_imatrix_vertices(int rows, int cols, const double* lo, const double* hi, int* count,
                        double* out) {
  return guard("sb_imatrix_vertices", [&] {
    const IntervalMatrix m = imatrix_arg(lo, hi, rows, cols, "M");
    require_pointer(count, "count");
    const int q = m.uncertain_count();
    // Too many entries or unbounded uncertain entries: vertices() throws the named error.
    if (q > IntervalMatrix::kMaxVertexEntries || !m.lo().allFinite() || !m.hi().allFinite())
      m.vertices("M");
    const int needed = 1 << q;
    const int capacity = *count;
    if (capacity < needed) {
      *count = needed;
      throw BufferTooSmallError("count: capacity " + std::to_string(capacity) +
                                " is below the " + std::to_string(needed) + " vertices (2^" +
                                std::to_string(q) + ")");
    }
    const auto verts = m.vertices("M");
    const std::size_t block = std::size_t(rows) * std::size_t(cols);
    if (block > 0) require_pointer(out, "out");
    for (std::size_t v = 0; v < verts.size(); ++v)
      RowMap(out + v * block, rows, cols) = verts[v];
    *count = needed;
  });
}

int sb_imatrix_norm(int rows, int cols, const double* lo, const double* hi, double* norm) {
  return guard("sb_imatrix_norm", [&] {
    const IntervalMatrix m = imatrix_arg(lo, hi, rows, cols, "M");
    require_pointer(norm, "norm");
    *norm = m.norm();
  });
}

}  // extern "C"
