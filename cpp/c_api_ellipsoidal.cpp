// setbound — C ABI: the ellipsoidal estimators, descriptor systems and the Kalman baseline.
#include <memory>
#include <optional>
#include <utility>
#include <variant>

#include "c_api_handles.hpp"
#include "setbound/estimators/ellipsoidal/descriptor.hpp"
#include "setbound/estimators/ellipsoidal/lmi_estimators.hpp"
#include "setbound/estimators/ellipsoidal/improved_estimator.hpp"
#include "setbound/estimators/point/kalman.hpp"

using namespace setbound;
using namespace setbound::capi;

struct sb_ell_design {
  EllDesign design;
  bool descriptor;
};

struct sb_descriptor_system {
  DescriptorSystem system;
};

struct sb_ellipsoidal {
  template <class Estimator>
  sb_ellipsoidal(Estimator&& e, int m) : estimator(std::forward<Estimator>(e)), method(m) {}

  std::variant<EllipsoidalPredictor, ImprovedEstimator, DescriptorEstimator> estimator;
  int method;
  std::vector<double> initial_state;  // DESCRIPTOR: what sb_ellipsoidal_reset restores
  bool fallback = false;
  double beta = 0.0;
  Eigen::MatrixXd gain;
};

struct sb_kalman {
  KalmanFilter filter;
  int ny, nu;
};

namespace {


EllNormalization normalization_arg(int n) {
  switch (n) {
    case SB_ELL_NORM_LOGDET: return EllNormalization::LogDet;
    case SB_ELL_NORM_BALL: return EllNormalization::Ball;
    case SB_ELL_NORM_PAPER_TRACE: return EllNormalization::PaperTrace;
    default: throw InvalidArgumentError("normalization: unknown value " + std::to_string(n));
  }
}

EllDesignOptions design_options(int normalization, double beta) {
  EllDesignOptions o;
  o.normalization = normalization_arg(normalization);
  if (!std::isnan(beta)) {
    if (!(beta > 0.0 && beta < 1.0)) throw InvalidArgumentError("beta: must be in (0, 1) or NaN, got " + std::to_string(beta));
    o.beta = beta;
  }
  return o;
}

EllPredictorMode predictor_arg(int m, const char* name) {
  switch (m) {
    case SB_ELL_OFFLINE: return EllPredictorMode::Offline;
    case SB_ELL_ONLINE_VERTEX: return EllPredictorMode::OnlineVertex;
    case SB_ELL_ONLINE_SCALED: return EllPredictorMode::OnlineScaled;
    default: throw InvalidArgumentError(std::string(name) + ": not a prediction method: " + std::to_string(m));
  }
}

/// The current set and its reported bounds.
struct Current {
  const Ellipsoid* set;
  Eigen::VectorXd lower, upper;
};

Current current_of(const sb_ellipsoidal& e) {
  return std::visit(
      [](const auto& est) -> Current {
        using T = std::decay_t<decltype(est)>;
        if constexpr (std::is_same_v<T, ImprovedEstimator>) {
          return {&est.current(), est.lower(), est.upper()};
        } else {
          const BoundingBox b = est.current().bounding_box();
          return {&est.current(), b.lo, b.hi};
        }
      },
      e.estimator);
}

void write_current(const sb_ellipsoidal& e, double* P, double* c, double* rho, double* lower, double* upper) {
  const Current cur = current_of(e);
  write_matrix(cur.set->shape(), P);
  write_vector(cur.set->center(), c);
  if (rho != nullptr) *rho = cur.set->level();
  write_vector(cur.lower, lower);
  write_vector(cur.upper, upper);
}

const EllDesign& design_of(const sb_ellipsoidal& e) {
  return std::visit([](const auto& est) -> const EllDesign& { return est.design(); }, e.estimator);
}

}  // namespace

extern "C" {

int sb_ell_design_offline(const sb_linear_system* system, int normalization, double beta, sb_ell_design** out) {
  return guard("sb_ell_design_offline", [&] {
    require_pointer(out, "out");
    *out = nullptr;
    const LinearSystem& sys = system_arg(system);
    *out = new sb_ell_design{design_ellipsoidal_offline(sys, design_options(normalization, beta)), false};
  });
}

int sb_descriptor_system_create(int nx, int ny, int nu, int nw, const double* E, const double* A, const double* B,
                                const double* C, const double* D, const double* F, sb_descriptor_system** out) {
  return guard("sb_descriptor_system_create", [&] {
    require_pointer(out, "out");
    *out = nullptr;
    require_dimension(nx, "nx");
    require_dimension(ny, "ny");
    require_dimension(nu, "nu", true);
    require_dimension(nw, "nw", true);
    Eigen::MatrixXd Bm = nu > 0 ? Eigen::MatrixXd(matrix_arg(B, nx, nu, "B")) : Eigen::MatrixXd();
    *out = new sb_descriptor_system{DescriptorSystem(
        matrix_arg(E, nx, nx, "E"), matrix_arg(A, nx, nx, "A"), matrix_arg(C, ny, nx, "C"),
        nw > 0 ? Eigen::MatrixXd(matrix_arg(D, nx, nw, "D")) : Eigen::MatrixXd::Zero(nx, 0),
        nw > 0 ? Eigen::MatrixXd(matrix_arg(F, ny, nw, "F")) : Eigen::MatrixXd::Zero(ny, 0), Bm)};
  });
}

int sb_descriptor_system_free(sb_descriptor_system* system) {
  delete system;
  return SB_OK;
}

int sb_descriptor_system_tn(const sb_descriptor_system* system, double* T, double* N) {
  return guard("sb_descriptor_system_tn", [&] {
    require_pointer(system, "system");
    write_matrix(system->system.T(), T);
    write_matrix(system->system.N(), N);
  });
}

int sb_ell_design_descriptor(const sb_descriptor_system* system, int normalization, double beta,
                             sb_ell_design** out) {
  return guard("sb_ell_design_descriptor", [&] {
    require_pointer(out, "out");
    *out = nullptr;
    require_pointer(system, "system");
    *out = new sb_ell_design{design_descriptor_offline(system->system, design_options(normalization, beta)), true};
  });
}

int sb_ell_design_free(sb_ell_design* design) {
  delete design;
  return SB_OK;
}

int sb_ell_design_dims(const sb_ell_design* design, int* nx, int* ny) {
  return guard("sb_ell_design_dims", [&] {
    require_pointer(design, "design");
    if (nx) *nx = static_cast<int>(design->design.P.rows());
    if (ny) *ny = static_cast<int>(design->design.L.cols());
  });
}

int sb_ell_design_get(const sb_ell_design* design, double* P, double* L, double* scalars, int* vertex_blocks,
                      int* normalization) {
  return guard("sb_ell_design_get", [&] {
    require_pointer(design, "design");
    const EllDesign& d = design->design;
    write_matrix(d.P, P);
    write_matrix(d.L, L);
    if (scalars) {
      scalars[0] = d.beta;
      scalars[1] = d.sigma;
      scalars[2] = d.rho_inf;
      scalars[3] = d.volume_inf;
    }
    if (vertex_blocks) *vertex_blocks = d.vertex_blocks;
    if (normalization) *normalization = static_cast<int>(d.normalization);
  });
}

int sb_ellipsoidal_create(const sb_ell_design* design, int method, int option, int feedback, int predictor,
                          const sb_descriptor_system* descriptor, const double* P0, const double* c0, double rho0,
                          sb_ellipsoidal** out) {
  return guard("sb_ellipsoidal_create", [&] {
    require_pointer(out, "out");
    *out = nullptr;
    require_pointer(design, "design");
    const EllDesign& d = design->design;
    const int nx = static_cast<int>(d.P.rows());
    Ellipsoid x0(matrix_arg(P0, nx, nx, "P0"), vector_arg(c0, nx, "c0"), rho0);
    if (method == SB_ELL_DESCRIPTOR) {
      if (descriptor == nullptr)
        throw InvalidArgumentError("descriptor: the descriptor method needs the descriptor system");
      if (!design->descriptor)
        throw InvalidArgumentError("design: the descriptor method needs a design made for a descriptor system");
      *out = new sb_ellipsoidal{DescriptorEstimator(d, descriptor->system, x0), method};
      (*out)->initial_state = std::get<DescriptorEstimator>((*out)->estimator).save_state();
      return;
    }
    if (design->descriptor)
      throw InvalidArgumentError("design: a descriptor-system design is only usable with the descriptor method");
    if (method == SB_ELL_IMPROVED) {
      CorrectionOption opt;
      switch (option) {
        case SB_ELL_CORR_FIXED_SHAPE: opt = CorrectionOption::FixedShape; break;
        case SB_ELL_CORR_DET_NORMALIZED: opt = CorrectionOption::DetNormalized; break;
        case SB_ELL_CORR_BALL_NORMALIZED: opt = CorrectionOption::BallNormalized; break;
        default: throw InvalidArgumentError("option: unknown correction option " + std::to_string(option));
      }
      ImprovedFeedback fb;
      switch (feedback) {
        case SB_ELL_FEEDBACK_NONE: fb = ImprovedFeedback::None; break;
        case SB_ELL_FEEDBACK_OUTER_BOUND: fb = ImprovedFeedback::OuterBound; break;
        case SB_ELL_FEEDBACK_FIXED_SHAPE: fb = ImprovedFeedback::FixedShape; break;
        default: throw InvalidArgumentError("feedback: unknown feedback rule " + std::to_string(feedback));
      }
      *out = new sb_ellipsoidal{ImprovedEstimator(d, x0, opt, fb, predictor_arg(predictor, "predictor")), method};
      return;
    }
    *out = new sb_ellipsoidal{EllipsoidalPredictor(d, x0, predictor_arg(method, "method")), method};
  });
}

int sb_ellipsoidal_free(sb_ellipsoidal* estimator) {
  delete estimator;
  return SB_OK;
}

int sb_ellipsoidal_info(const sb_ellipsoidal* estimator, int* is_filter, int* steps, int* nx, int* ny, int* nu) {
  return guard("sb_ellipsoidal_info", [&] {
    require_pointer(estimator, "estimator");
    const EllDesign& d = design_of(*estimator);
    if (is_filter) *is_filter = (estimator->method == SB_ELL_IMPROVED || estimator->method == SB_ELL_DESCRIPTOR) ? 1 : 0;
    if (steps)
      *steps = static_cast<int>(std::visit([](const auto& est) { return est.steps_taken(); }, estimator->estimator));
    if (nx) *nx = static_cast<int>(d.P.rows());
    if (ny) *ny = static_cast<int>(d.system.ny());
    if (nu) {
      if (const auto* de = std::get_if<DescriptorEstimator>(&estimator->estimator))
        *nu = static_cast<int>(de->system().nu());
      else
        *nu = static_cast<int>(d.system.nu());
    }
  });
}

int sb_ellipsoidal_current(const sb_ellipsoidal* estimator, double* P, double* c, double* rho, double* lower,
                           double* upper) {
  return guard("sb_ellipsoidal_current", [&] {
    require_pointer(estimator, "estimator");
    write_current(*estimator, P, c, rho, lower, upper);
  });
}

int sb_ellipsoidal_step(sb_ellipsoidal* estimator, const double* y, const double* u, double* P, double* c,
                        double* rho, double* lower, double* upper) {
  return guard("sb_ellipsoidal_step", [&] {
    require_pointer(estimator, "estimator");
    int ny = 0, nu = 0;
    sb_ellipsoidal_info(estimator, nullptr, nullptr, nullptr, &ny, &nu);
    const Eigen::VectorXd yv = vector_arg(y, ny, "y");
    const Eigen::VectorXd uv = vector_arg(u, nu, "u");
    std::visit(
        [&](auto& est) {
          using T = std::decay_t<decltype(est)>;
          if constexpr (std::is_same_v<T, EllipsoidalPredictor>) {
            const Eigen::Index before = est.fallback_steps();
            est.step(yv, uv);
            estimator->beta = est.last_beta();
            estimator->gain = est.last_gain();
            estimator->fallback = est.fallback_steps() > before;
          } else if constexpr (std::is_same_v<T, ImprovedEstimator>) {
            const Eigen::Index before = est.predictor().fallback_steps();
            est.step(yv, uv);
            estimator->beta = est.predictor().last_beta();
            estimator->gain = est.predictor().last_gain();
            estimator->fallback = est.predictor().fallback_steps() > before;
          } else {
            est.step(yv, uv);
            estimator->beta = est.design().beta;
            estimator->gain = est.design().L;
            estimator->fallback = false;
          }
        },
        estimator->estimator);
    write_current(*estimator, P, c, rho, lower, upper);
  });
}

int sb_ellipsoidal_last_step(const sb_ellipsoidal* estimator, double* beta, double* L, int* fallback) {
  return guard("sb_ellipsoidal_last_step", [&] {
    require_pointer(estimator, "estimator");
    if (beta) *beta = estimator->beta;
    if (L && estimator->gain.size() > 0) write_matrix(estimator->gain, L);
    if (fallback) *fallback = estimator->fallback ? 1 : 0;
  });
}

int sb_ellipsoidal_set_reuse_tolerance(sb_ellipsoidal* estimator, double tol) {
  return guard("sb_ellipsoidal_set_reuse_tolerance", [&] {
    require_pointer(estimator, "estimator");
    auto* pred = std::get_if<EllipsoidalPredictor>(&estimator->estimator);
    if (pred == nullptr || pred->mode() == EllPredictorMode::Offline)
      throw InvalidArgumentError("estimator: the reuse tolerance applies to the online predictors only");
    pred->set_reuse_tolerance(tol);
  });
}

int sb_ellipsoidal_online_solves(const sb_ellipsoidal* estimator, int* solves) {
  return guard("sb_ellipsoidal_online_solves", [&] {
    require_pointer(estimator, "estimator");
    require_pointer(solves, "solves");
    const auto* pred = std::get_if<EllipsoidalPredictor>(&estimator->estimator);
    *solves = pred != nullptr ? static_cast<int>(pred->online_solves()) : 0;
  });
}

int sb_ellipsoidal_set_inconsistency_policy(sb_ellipsoidal* estimator, int policy, const double* P0,
                                            const double* c0, double rho0) {
  return guard("sb_ellipsoidal_set_inconsistency_policy", [&] {
    require_pointer(estimator, "estimator");
    const OnInconsistency pol = inconsistency_policy_arg(policy);
    std::visit(
        [&](auto& est) {
          using T = std::decay_t<decltype(est)>;
          if constexpr (std::is_same_v<T, DescriptorEstimator>) {
            if (pol != OnInconsistency::Flag || P0 != nullptr)
              throw InvalidArgumentError(
                  "policy: the descriptor estimator needs every output (setbound docs: Methods › Ellipsoidal estimation › Descriptor systems), it cannot skip or restart "
                  "on a reading; only SB_ON_INCONSISTENCY_FLAG without a reset set is accepted");
          } else {
            if (P0 == nullptr) {
              est.set_inconsistency_policy(pol);
              return;
            }
            const int nx = static_cast<int>(est.design().system.nx());
            est.set_inconsistency_policy(pol, Ellipsoid(matrix_arg(P0, nx, nx, "P0"), vector_arg(c0, nx, "c0"), rho0));
          }
        },
        estimator->estimator);
  });
}

int sb_ellipsoidal_last_check(const sb_ellipsoidal* estimator, int* status, double* margin, int* reset) {
  return guard("sb_ellipsoidal_last_check", [&] {
    require_pointer(estimator, "estimator");
    std::visit(
        [&](const auto& est) {
          using T = std::decay_t<decltype(est)>;
          if constexpr (std::is_same_v<T, DescriptorEstimator>) {
            MeasurementCheck c;  // every output is used (or the estimator has not started)
            c.clear(est.system().ny(), est.steps_taken() > 0 ? OutputStatus::Used : OutputStatus::Unused);
            check_out(c, status, margin, reset);
          } else {
            check_out(est.last_check(), status, margin, reset);
          }
        },
        estimator->estimator);
  });
}

int sb_ellipsoidal_reset(sb_ellipsoidal* estimator) {
  return guard("sb_ellipsoidal_reset", [&] {
    require_pointer(estimator, "estimator");
    std::visit(
        [&](auto& est) {
          using T = std::decay_t<decltype(est)>;
          if constexpr (std::is_same_v<T, DescriptorEstimator>) est.restore_state(estimator->initial_state);
          else est.reset();
        },
        estimator->estimator);
    estimator->fallback = false;
    estimator->beta = 0.0;
    estimator->gain.resize(0, 0);
  });
}

int sb_kalman_create(const sb_linear_system* system, const double* mean0, const double* cov0, const double* W,
                     sb_kalman** out) {
  return guard("sb_kalman_create", [&] {
    require_pointer(out, "out");
    *out = nullptr;
    const LinearSystem& sys = system_arg(system);
    const int nx = static_cast<int>(sys.nx()), nw = static_cast<int>(sys.nw());
    Eigen::MatrixXd Wm = W != nullptr ? Eigen::MatrixXd(matrix_arg(W, nw, nw, "W")) : Eigen::MatrixXd();
    *out = new sb_kalman{KalmanFilter(sys, vector_arg(mean0, nx, "mean0"), matrix_arg(cov0, nx, nx, "cov0"), Wm),
                         static_cast<int>(sys.ny()), static_cast<int>(sys.nu())};
  });
}

int sb_kalman_free(sb_kalman* filter) {
  delete filter;
  return SB_OK;
}

int sb_kalman_step(sb_kalman* filter, const double* y, const double* u, double* mean, double* cov) {
  return guard("sb_kalman_step", [&] {
    require_pointer(filter, "filter");
    filter->filter.step(vector_arg(y, filter->ny, "y"), vector_arg(u, filter->nu, "u"));
    write_vector(filter->filter.mean(), mean);
    write_matrix(filter->filter.covariance(), cov);
  });
}

int sb_ellipsoidal_state_size(const sb_ellipsoidal* estimator, int* n) {
  return guard("sb_ellipsoidal_state_size", [&] {
    require_pointer(estimator, "estimator");
    state_size_out(std::visit([](const auto& est) { return est.save_state(); }, estimator->estimator), n);
  });
}

int sb_ellipsoidal_save_state(const sb_ellipsoidal* estimator, double* state, int n) {
  return guard("sb_ellipsoidal_save_state", [&] {
    require_pointer(estimator, "estimator");
    state_copy_out(std::visit([](const auto& est) { return est.save_state(); }, estimator->estimator), state, n);
  });
}

int sb_ellipsoidal_restore_state(sb_ellipsoidal* estimator, const double* state, int n) {
  return guard("sb_ellipsoidal_restore_state", [&] {
    require_pointer(estimator, "estimator");
    const std::vector<double> s = state_arg(state, n);
    std::visit(
        [&](auto& est) {
          using T = std::decay_t<decltype(est)>;
          est.restore_state(s);
          if constexpr (std::is_same_v<T, EllipsoidalPredictor>) {
            estimator->beta = est.last_beta();
            estimator->gain = est.last_gain();
          } else if constexpr (std::is_same_v<T, ImprovedEstimator>) {
            estimator->beta = est.predictor().last_beta();
            estimator->gain = est.predictor().last_gain();
          } else {
            estimator->beta = est.design().beta;
            estimator->gain = est.design().L;
          }
          estimator->fallback = false;
        },
        estimator->estimator);
  });
}

int sb_kalman_current(const sb_kalman* filter, double* mean, double* cov, int* steps) {
  return guard("sb_kalman_current", [&] {
    require_pointer(filter, "filter");
    write_vector(filter->filter.mean(), mean);
    write_matrix(filter->filter.covariance(), cov);
    if (steps) *steps = static_cast<int>(filter->filter.steps());
  });
}

int sb_kalman_state_size(const sb_kalman* filter, int* n) {
  return guard("sb_kalman_state_size", [&] {
    require_pointer(filter, "filter");
    state_size_out(filter->filter.save_state(), n);
  });
}

int sb_kalman_save_state(const sb_kalman* filter, double* state, int n) {
  return guard("sb_kalman_save_state", [&] {
    require_pointer(filter, "filter");
    state_copy_out(filter->filter.save_state(), state, n);
  });
}

int sb_kalman_restore_state(sb_kalman* filter, const double* state, int n) {
  return guard("sb_kalman_restore_state", [&] {
    require_pointer(filter, "filter");
    filter->filter.restore_state(state_arg(state, n));
  });
}


}  // extern "C"
