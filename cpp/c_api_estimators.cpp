// setbound — C ABI: system models and the zonotopic estimators.
#include <memory>
#include <optional>
#include <vector>

#include "c_api_handles.hpp"
#include "setbound/core/linear_system.hpp"
#include "setbound/estimators/polytopic/exact_hull.hpp"
#include "setbound/estimators/zonotopic/pradius.hpp"
#include "setbound/estimators/zonotopic/volume_min.hpp"
#include "setbound/estimators/zonotopic/gain_estimator.hpp"

using namespace setbound;
using namespace setbound::capi;

struct sb_zonotopic {
  ZonotopicEstimator estimator;
};

namespace {

Eigen::MatrixXd optional_matrix(const double* data, int rows, int cols, const char* name) {
  if (data == nullptr) return Eigen::MatrixXd();
  return matrix_arg(data, rows, cols, name);
}

}  // namespace

extern "C" {

int sb_linear_system_create(int nx, int ny, int nu, int nw, const double* A, const double* B,
                            const double* C, const double* D, const double* E, const double* F,
                            const double* A_rad, sb_linear_system** out) {
  return guard("sb_linear_system_create", [&] {
    require_pointer(out, "out");
    *out = nullptr;
    require_dimension(nx, "nx");
    require_dimension(ny, "ny");
    require_dimension(nu, "nu", true);
    require_dimension(nw, "nw", true);
    require_pointer(A, "A");
    require_pointer(C, "C");
    if (nw > 0) require_pointer(E, "E"), require_pointer(F, "F");
    if (nu > 0 && B == nullptr) throw InvalidArgumentError("B: null pointer but nu = " + std::to_string(nu));
    Eigen::MatrixXd Bm = nu > 0 ? Eigen::MatrixXd(matrix_arg(B, nx, nu, "B")) : Eigen::MatrixXd::Zero(nx, 0);
    Eigen::MatrixXd Dm = nu > 0 ? optional_matrix(D, ny, nu, "D") : Eigen::MatrixXd::Zero(ny, 0);
    auto s = std::make_unique<sb_linear_system>(sb_linear_system{LinearSystem(
        matrix_arg(A, nx, nx, "A"), matrix_arg(C, ny, nx, "C"),
        nw > 0 ? Eigen::MatrixXd(matrix_arg(E, nx, nw, "E")) : Eigen::MatrixXd::Zero(nx, 0),
        nw > 0 ? Eigen::MatrixXd(matrix_arg(F, ny, nw, "F")) : Eigen::MatrixXd::Zero(ny, 0), Bm, Dm,
        optional_matrix(A_rad, nx, nx, "A_rad"))});
    *out = s.release();
  });
}

int sb_linear_system_free(sb_linear_system* system) {
  delete system;
  return SB_OK;
}

int sb_linear_system_dims(const sb_linear_system* system, int* nx, int* ny, int* nu, int* nw) {
  return guard("sb_linear_system_dims", [&] {
    const LinearSystem& s = system_arg(system);
    if (nx) *nx = static_cast<int>(s.nx());
    if (ny) *ny = static_cast<int>(s.ny());
    if (nu) *nu = static_cast<int>(s.nu());
    if (nw) *nw = static_cast<int>(s.nw());
  });
}

int sb_check_detectability(int nx, int ny, const double* A, const double* C, int* detectable,
                           double* mode_re, double* mode_im) {
  return guard("sb_check_detectability", [&] {
    require_dimension(nx, "nx");
    require_dimension(ny, "ny");
    require_pointer(A, "A");
    require_pointer(C, "C");
    require_pointer(detectable, "detectable");
    const DetectabilityReport r =
        check_detectability(matrix_arg(A, nx, nx, "A"), matrix_arg(C, ny, nx, "C"));
    *detectable = r.detectable ? 1 : 0;
    if (mode_re) *mode_re = r.mode.real();
    if (mode_im) *mode_im = r.mode.imag();
  });
}

int sb_zonotopic_create(const sb_linear_system* system, int gain, const double* lambdas,
                        int max_generators, int use_first_measurement, const int* strip_order,
                        int m0, const double* p0, const double* H0, sb_zonotopic** out) {
  return guard("sb_zonotopic_create", [&] {
    require_pointer(out, "out");
    *out = nullptr;
    const LinearSystem& sys = system_arg(system);
    std::optional<ZonotopeGain> rule;
    switch (gain) {
      case SB_ZONO_GAIN_SEGMENT_MIN: rule.emplace(segment_min_gain); break;
      case SB_ZONO_GAIN_VOLUME_MIN: rule.emplace(volume_min_gain); break;
      case SB_ZONO_GAIN_FIXED: {
        require_pointer(lambdas, "lambdas");
        rule.emplace(ZonotopeGain::fixed(
            matrix_arg(lambdas, static_cast<int>(sys.ny()), static_cast<int>(sys.nx()), "lambdas")));
        break;
      }
      default: throw InvalidArgumentError("gain: unknown gain rule " + std::to_string(gain));
    }
    require_dimension(m0, "m0", true);
    const int nx = static_cast<int>(sys.nx());
    Zonotope x0(vector_arg(p0, nx, "p0"),
                m0 > 0 ? Eigen::MatrixXd(matrix_arg(H0, nx, m0, "H0")) : Eigen::MatrixXd::Zero(nx, 0));
    // The estimator allocates n_x x max_generators work matrices up front: a count far beyond any
    // use is refused with its name, not as "out of memory".
    if (max_generators > SB_ZONO_MAX_GENERATORS)
      throw InvalidArgumentError("max_generators: at most " + std::to_string(SB_ZONO_MAX_GENERATORS) + ", got " +
                                 std::to_string(max_generators));
    ZonotopicOptions opt;
    opt.max_generators = max_generators;
    opt.use_first_measurement = use_first_measurement != 0;
    if (strip_order != nullptr)
      opt.strip_order.assign(strip_order, strip_order + sys.ny());
    auto est = std::make_unique<sb_zonotopic>(sb_zonotopic{ZonotopicEstimator(sys, x0, std::move(*rule), std::move(opt))});
    *out = est.release();
  });
}

int sb_zonotopic_free(sb_zonotopic* estimator) {
  delete estimator;
  return SB_OK;
}

int sb_zonotopic_set_reduction(sb_zonotopic* estimator, int method) {
  return guard("sb_zonotopic_set_reduction", [&] {
    require_pointer(estimator, "estimator");
    switch (method) {
      case SB_ZONO_REDUCE_COMBASTEL: estimator->estimator.set_reduction(ZonotopeReduction::Combastel); break;
      case SB_ZONO_REDUCE_GIRARD: estimator->estimator.set_reduction(ZonotopeReduction::Girard); break;
      case SB_ZONO_REDUCE_PCA: estimator->estimator.set_reduction(ZonotopeReduction::Pca); break;
      default:
        throw InvalidArgumentError("method: unknown reduction method " + std::to_string(method) +
                                   " (SB_ZONO_REDUCE_COMBASTEL = 1, SB_ZONO_REDUCE_GIRARD = 2, SB_ZONO_REDUCE_PCA = 3)");
    }
  });
}

int sb_zonotopic_set_inconsistency_policy(sb_zonotopic* estimator, int policy, int m, const double* p,
                                          const double* H) {
  return guard("sb_zonotopic_set_inconsistency_policy", [&] {
    require_pointer(estimator, "estimator");
    ZonotopicEstimator& est = estimator->estimator;
    const OnInconsistency pol = inconsistency_policy_arg(policy);
    if (p == nullptr) {
      est.set_inconsistency_policy(pol);
      return;
    }
    require_dimension(m, "m", true);
    const int nx = static_cast<int>(est.system().nx());
    est.set_inconsistency_policy(
        pol, Zonotope(vector_arg(p, nx, "p"),
                      m > 0 ? Eigen::MatrixXd(matrix_arg(H, nx, m, "H")) : Eigen::MatrixXd::Zero(nx, 0)));
  });
}

int sb_zonotopic_last_check(const sb_zonotopic* estimator, int* status, double* margin, int* reset) {
  return guard("sb_zonotopic_last_check", [&] {
    require_pointer(estimator, "estimator");
    check_out(estimator->estimator.last_check(), status, margin, reset);
  });
}

int sb_zonotopic_reset(sb_zonotopic* estimator) {
  return guard("sb_zonotopic_reset", [&] {
    require_pointer(estimator, "estimator");
    estimator->estimator.reset();
  });
}

int sb_zonotopic_steps(const sb_zonotopic* estimator, int* steps) {
  return guard("sb_zonotopic_steps", [&] {
    require_pointer(estimator, "estimator");
    require_pointer(steps, "steps");
    *steps = static_cast<int>(std::min<Eigen::Index>(estimator->estimator.steps_taken(), std::numeric_limits<int>::max()));
  });
}

int sb_zonotopic_step(sb_zonotopic* estimator, const double* y, const double* u, double* center,
                      double* lower, double* upper, int* m) {
  return guard("sb_zonotopic_step", [&] {
    require_pointer(estimator, "estimator");
    ZonotopicEstimator& est = estimator->estimator;
    const LinearSystem& sys = est.system();
    const int nx = static_cast<int>(sys.nx());
    const int nu = static_cast<int>(sys.nu());
    require_pointer(center, "center");
    require_pointer(lower, "lower");
    require_pointer(upper, "upper");
    require_pointer(m, "m");
    if (nu > 0) require_pointer(u, "u");
    if (nu > 0) est.update(vector_arg(y, static_cast<int>(sys.ny()), "y"), vector_arg(u, nu, "u"));
    else est.update(vector_arg(y, static_cast<int>(sys.ny()), "y"), Eigen::VectorXd(0));
    VecMap(center, nx) = est.current_center();
    VecMap(lower, nx) = est.current_lower();
    VecMap(upper, nx) = est.current_upper();
    *m = static_cast<int>(est.current_num_generators());
  });
}

int sb_zonotopic_last_set(const sb_zonotopic* estimator, int* m, double* p, double* H) {
  return guard("sb_zonotopic_last_set", [&] {
    require_pointer(estimator, "estimator");
    require_pointer(m, "m");
    const ZonotopicEstimator& est = estimator->estimator;
    if (!est.has_current()) throw InvalidArgumentError("estimator: no step has been taken yet");
    const int need = static_cast<int>(est.current_num_generators());
    if (*m < need) {
      const int capacity = *m;
      *m = need;
      throw BufferTooSmallError("m: capacity " + std::to_string(capacity) + " < " + std::to_string(need) +
                                " generators");
    }
    *m = need;
    const int nx = static_cast<int>(est.system().nx());
    require_pointer(p, "p");
    VecMap(p, nx) = est.current_center();
    if (need > 0) {
      require_pointer(H, "H");
      // The generators, then the pending rounding box as axis-aligned columns.
      auto out = RowMap(H, nx, need);
      const auto G = est.current_generators();
      out.leftCols(G.cols()) = G;
      Eigen::Index j = G.cols();
      for (Eigen::Index i = 0; i < nx; ++i)
        if (est.current_box()(i) > 0) {
          out.col(j).setZero();
          out(i, j++) = est.current_box()(i);
        }
    }
  });
}

int sb_pradius_design(const sb_linear_system* system, int approach, const int* strip_order,
                      int try_all_orders, double beta_lo, double beta_hi, double* lambdas,
                      double* P, double* beta, double* tau, double* psi, int* order_out) {
  return guard("sb_pradius_design", [&] {
    const LinearSystem& sys = system_arg(system);
    PRadiusOptions opt;
    if (approach == 1) opt.approach = PRadiusApproach::Sequential;
    else if (approach == 2) opt.approach = PRadiusApproach::Coupled;
    else throw InvalidArgumentError("approach: must be 1 (sequential) or 2 (coupled), got " + std::to_string(approach));
    if (strip_order != nullptr) opt.strip_order.assign(strip_order, strip_order + sys.ny());
    opt.try_all_orders = try_all_orders != 0;
    require_finite(beta_lo, "beta_lo");
    require_finite(beta_hi, "beta_hi");
    opt.beta_lo = beta_lo;
    opt.beta_hi = beta_hi;
    require_pointer(lambdas, "lambdas");
    require_pointer(P, "P");
    require_pointer(beta, "beta");
    require_pointer(tau, "tau");
    const PRadiusDesign d = design_pradius(sys, opt);
    const Eigen::Index n = sys.nx(), ny = sys.ny();
    RowMap(lambdas, ny, n) = d.lambdas;
    for (Eigen::Index i = 0; i < ny; ++i) RowMap(P + i * n * n, n, n) = d.P[static_cast<std::size_t>(i)];
    VecMap(beta, ny) = d.beta;
    VecMap(tau, ny) = d.tau;
    if (psi) *psi = d.psi;
    if (order_out)
      for (Eigen::Index i = 0; i < ny; ++i) order_out[i] = static_cast<int>(d.strip_order[static_cast<std::size_t>(i)]);
  });
}

int sb_exact_hull(const sb_linear_system* system, int m0, const double* p0, const double* H0,
                  int N, const double* Y, const double* U, int use_first_measurement,
                  double* lower, double* upper) {
  return guard("sb_exact_hull", [&] {
    const LinearSystem& sys = system_arg(system);
    const int nx = static_cast<int>(sys.nx()), ny = static_cast<int>(sys.ny()), nu = static_cast<int>(sys.nu());
    require_dimension(m0, "m0", true);
    require_dimension(N, "N");
    require_pointer(lower, "lower");
    require_pointer(upper, "upper");
    const Zonotope x0(vector_arg(p0, nx, "p0"),
                      m0 > 0 ? Eigen::MatrixXd(matrix_arg(H0, nx, m0, "H0")) : Eigen::MatrixXd::Zero(nx, 0));
    const Eigen::MatrixXd Ym = matrix_arg(Y, N, ny, "y");
    Eigen::MatrixXd Um;
    if (nu > 0) {
      require_pointer(U, "u");
      Um = matrix_arg(U, N, nu, "u");
    }
    const ExactHull h = exact_hull(sys, x0, Ym, Um, use_first_measurement != 0);
    RowMap(lower, N, nx) = h.lower;
    RowMap(upper, N, nx) = h.upper;
  });
}

int sb_zonotopic_state_size(const sb_zonotopic* estimator, int* n) {
  return guard("sb_zonotopic_state_size", [&] {
    require_pointer(estimator, "estimator");
    state_size_out(estimator->estimator.save_state(), n);
  });
}

int sb_zonotopic_save_state(const sb_zonotopic* estimator, double* state, int n) {
  return guard("sb_zonotopic_save_state", [&] {
    require_pointer(estimator, "estimator");
    state_copy_out(estimator->estimator.save_state(), state, n);
  });
}

int sb_zonotopic_restore_state(sb_zonotopic* estimator, const double* state, int n) {
  return guard("sb_zonotopic_restore_state", [&] {
    require_pointer(estimator, "estimator");
    estimator->estimator.restore_state(state_arg(state, n));
  });
}

}  // extern "C"
