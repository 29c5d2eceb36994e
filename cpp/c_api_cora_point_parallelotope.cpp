// setbound — C ABI: CORA's ROPO (recursive optimal parallelotopes, estimators/zonotopic/
// parallelotope.hpp) and the Rauch–Tung–Striebel smoother (estimators/point/rts_smoother.hpp).
#include <memory>
#include <string>
#include <vector>

#include "c_api_handles.hpp"
#include "setbound/estimators/point/rts_smoother.hpp"
#include "setbound/estimators/zonotopic/parallelotope.hpp"

using namespace setbound;
using namespace setbound::capi;

struct sb_ropo {
  ParallelotopeEstimator estimator;
};

namespace {

ParallelotopeOptions ropo_options_arg(const sb_ropo_options* o) {
  ParallelotopeOptions opt;
  if (o == nullptr) return opt;
  if (o->reduction != SB_ZONO_REDUCE_GIRARD && o->reduction != SB_ZONO_REDUCE_PCA)
    throw InvalidArgumentError("options.reduction: expected SB_ZONO_REDUCE_GIRARD (2) or SB_ZONO_REDUCE_PCA (3), got " +
                               std::to_string(o->reduction) + " (ROPO reduces to a parallelotope; Combastel's rule "
                               "is Girard's box at order 1)");
  if (o->convention != SB_CONVENTION_SETBOUND && o->convention != SB_CONVENTION_CORA)
    throw InvalidArgumentError("options.convention: expected SB_CONVENTION_SETBOUND (0) or SB_CONVENTION_CORA (1), got " +
                               std::to_string(o->convention));
  opt.reduction = static_cast<ZonotopeReduction>(o->reduction);
  opt.convention = static_cast<Convention>(o->convention);
  try {
    opt.on_inconsistency = inconsistency_policy_arg(o->on_inconsistency);
  } catch (const InvalidArgumentError& e) {
    throw InvalidArgumentError(std::string("options.on_inconsistency: ") + e.what());
  }
  return opt;
}

}  // namespace

extern "C" {

int sb_ropo_default_options(sb_ropo_options* options) {
  return guard("sb_ropo_default_options", [&] {
    require_pointer(options, "options");
    options->reduction = SB_ZONO_REDUCE_GIRARD;
    options->convention = SB_CONVENTION_SETBOUND;
    options->on_inconsistency = SB_ON_INCONSISTENCY_FLAG;
  });
}

int sb_ropo_create(const sb_linear_system* system, const sb_ropo_options* options, int m0, const double* p0,
                   const double* H0, sb_ropo** out) {
  return guard("sb_ropo_create", [&] {
    require_pointer(out, "out");
    *out = nullptr;
    const LinearSystem& sys = system_arg(system);
    const ParallelotopeOptions opt = ropo_options_arg(options);
    require_dimension(m0, "m0", true);
    if (m0 > SB_ZONO_MAX_GENERATORS)
      throw InvalidArgumentError("m0: at most " + std::to_string(SB_ZONO_MAX_GENERATORS) + " generators, got " +
                                 std::to_string(m0));
    const int nx = static_cast<int>(sys.nx());
    Zonotope x0(vector_arg(p0, nx, "p0"),
                m0 > 0 ? Eigen::MatrixXd(matrix_arg(H0, nx, m0, "H0")) : Eigen::MatrixXd::Zero(nx, 0));
    auto est = std::make_unique<sb_ropo>(sb_ropo{ParallelotopeEstimator(sys, x0, opt)});
    *out = est.release();
  });
}

int sb_ropo_free(sb_ropo* estimator) {
  delete estimator;
  return SB_OK;
}

int sb_ropo_step(sb_ropo* estimator, const double* y, const double* u, double* center, double* lower,
                 double* upper, int* m) {
  return guard("sb_ropo_step", [&] {
    require_pointer(estimator, "estimator");
    ParallelotopeEstimator& est = estimator->estimator;
    const int nx = static_cast<int>(est.system().nx()), ny = static_cast<int>(est.system().ny());
    const int nu = static_cast<int>(est.system().nu());
    const Eigen::VectorXd yv = vector_arg(y, ny, "y");
    const Eigen::VectorXd uv = nu > 0 ? Eigen::VectorXd(vector_arg(u, nu, "u")) : Eigen::VectorXd(0);
    est.update(yv, uv);
    if (center) VecMap(center, nx) = est.current_center();
    if (lower) VecMap(lower, nx) = est.current_lower();
    if (upper) VecMap(upper, nx) = est.current_upper();
    if (m) *m = static_cast<int>(est.current_generators().cols() + (est.current_box().array() > 0).count());
  });
}

int sb_ropo_run(sb_ropo* estimator, int N, const double* Y, const double* U, double* center, double* lower,
                double* upper) {
  return guard("sb_ropo_run", [&] {
    require_pointer(estimator, "estimator");
    const ParallelotopeEstimator& est = estimator->estimator;
    const int ny = static_cast<int>(est.system().ny()), nu = static_cast<int>(est.system().nu());
    require_dimension(N, "N", true);
    const Eigen::MatrixXd Ym = matrix_arg(Y, N, ny, "Y");
    const Eigen::MatrixXd Um = nu > 0 ? Eigen::MatrixXd(matrix_arg(U, N, nu, "U")) : Eigen::MatrixXd(N, 0);
    // On a copy: the handle changes only when the whole run succeeded.
    ParallelotopeEstimator work = est;
    const ParallelotopeTrajectory t = work.run(Ym, Um);
    write_matrix(t.center, center);
    write_matrix(t.lower, lower);
    write_matrix(t.upper, upper);
    estimator->estimator = std::move(work);
  });
}

int sb_ropo_current_set(const sb_ropo* estimator, int* m, double* p, double* H) {
  return guard("sb_ropo_current_set", [&] {
    require_pointer(estimator, "estimator");
    require_pointer(m, "m");
    const ParallelotopeEstimator& est = estimator->estimator;
    if (!est.has_current()) throw InvalidArgumentError("estimator: no step has been taken yet");
    const Zonotope z = est.current_set();
    const int need = static_cast<int>(z.num_generators());
    if (*m < need) {
      const int capacity = *m;
      *m = need;
      throw BufferTooSmallError("m: capacity " + std::to_string(capacity) + " < " + std::to_string(need) +
                                " generators");
    }
    *m = need;
    const int nx = static_cast<int>(est.system().nx());
    require_pointer(p, "p");
    VecMap(p, nx) = z.center();
    if (need > 0) {
      require_pointer(H, "H");
      RowMap(H, nx, need) = z.generators();
    }
  });
}

int sb_ropo_parallelotope(const sb_ropo* estimator, double* theta, double* T, double* box) {
  return guard("sb_ropo_parallelotope", [&] {
    require_pointer(estimator, "estimator");
    const ParallelotopeEstimator& est = estimator->estimator;
    if (!est.has_current()) throw InvalidArgumentError("estimator: no step has been taken yet");
    const Eigen::Index nx = est.system().nx();
    if (est.current_generators().cols() != nx)
      throw InvalidArgumentError("estimator: the current set is x0 itself (cora convention, step 0) with " +
                                 std::to_string(est.current_generators().cols()) + " generators, not a parallelotope");
    write_vector(est.current_center(), theta);
    write_matrix(est.current_generators(), T);
    write_vector(est.current_box(), box);
  });
}

int sb_ropo_last_check(const sb_ropo* estimator, int* status, double* margin, int* reset) {
  return guard("sb_ropo_last_check", [&] {
    require_pointer(estimator, "estimator");
    check_out(estimator->estimator.last_check(), status, margin, reset);
  });
}

int sb_ropo_reset(sb_ropo* estimator) {
  return guard("sb_ropo_reset", [&] {
    require_pointer(estimator, "estimator");
    estimator->estimator.reset();
  });
}

int sb_ropo_steps(const sb_ropo* estimator, int* steps) {
  return guard("sb_ropo_steps", [&] {
    require_pointer(estimator, "estimator");
    require_pointer(steps, "steps");
    *steps = static_cast<int>(estimator->estimator.steps_taken());
  });
}

int sb_ropo_state_size(const sb_ropo* estimator, int* n) {
  return guard("sb_ropo_state_size", [&] {
    require_pointer(estimator, "estimator");
    state_size_out(estimator->estimator.save_state(), n);
  });
}

int sb_ropo_save_state(const sb_ropo* estimator, double* state, int n) {
  return guard("sb_ropo_save_state", [&] {
    require_pointer(estimator, "estimator");
    state_copy_out(estimator->estimator.save_state(), state, n);
  });
}

int sb_ropo_restore_state(sb_ropo* estimator, const double* state, int n) {
  return guard("sb_ropo_restore_state", [&] {
    require_pointer(estimator, "estimator");
    estimator->estimator.restore_state(state_arg(state, n));
  });
}

int sb_rts_smooth(const sb_linear_system* system, const double* x0, const double* P0, const double* Sigma_w,
                  const double* Sigma_v, int N, const double* Y, const double* U, int use_first_measurement,
                  double* smoothed, double* smoothed_cov, double* filtered, double* filtered_cov) {
  return guard("sb_rts_smooth", [&] {
    const LinearSystem& sys = system_arg(system);
    const int nx = static_cast<int>(sys.nx()), ny = static_cast<int>(sys.ny()), nu = static_cast<int>(sys.nu());
    require_dimension(N, "N", true);
    if (use_first_measurement != 0 && use_first_measurement != 1)
      throw InvalidArgumentError("use_first_measurement: expected 0 or 1, got " + std::to_string(use_first_measurement));
    const Eigen::VectorXd x = vector_arg(x0, nx, "x0");
    const Eigen::MatrixXd P = matrix_arg(P0, nx, nx, "P0");
    const Eigen::MatrixXd Sw = matrix_arg(Sigma_w, nx, nx, "Sigma_w");
    const Eigen::MatrixXd Sv = matrix_arg(Sigma_v, ny, ny, "Sigma_v");
    const Eigen::MatrixXd Ym = matrix_arg(Y, N, ny, "Y");
    const Eigen::MatrixXd Um = nu > 0 ? Eigen::MatrixXd(matrix_arg(U, N, nu, "U")) : Eigen::MatrixXd();
    RtsOptions opt;
    opt.use_first_measurement = use_first_measurement == 1;
    const RtsResult r = rts_smooth(sys, x, P, Sw, Sv, Ym, Um, opt);
    write_matrix(r.smoothed, smoothed);
    write_matrix(r.filtered, filtered);
    const std::size_t block = static_cast<std::size_t>(nx) * static_cast<std::size_t>(nx);
    for (int k = 0; k < N; ++k) {
      if (smoothed_cov) write_matrix(r.smoothed_cov[static_cast<std::size_t>(k)], smoothed_cov + k * block);
      if (filtered_cov) write_matrix(r.filtered_cov[static_cast<std::size_t>(k)], filtered_cov + k * block);
    }
  });
}

}  // extern "C"
