// setbound — C ABI: CORA's ellipsoidal and interval observers (issue 22): ESO-A / ESO-B
// (estimators/ellipsoidal/bounding_ellipsoid.hpp).
#include <utility>

#include "c_api_handles.hpp"
#include "setbound/estimators/ellipsoidal/bounding_ellipsoid.hpp"
#include "setbound/estimators/interval/cora_interval_observer.hpp"

using namespace setbound;
using namespace setbound::capi;

struct sb_bounding_ellipsoid {
  BoundingEllipsoidEstimator estimator;
};

struct sb_cora_interval {
  CoraIntervalObserver observer;
};

namespace {

BoundingRule bounding_rule_arg(int rule) {
  switch (rule) {
    case SB_BE_GOLLAMUDI: return BoundingRule::Gollamudi;
    case SB_BE_LIU: return BoundingRule::Liu;
    default: throw InvalidArgumentError("rule: unknown value " + std::to_string(rule));
  }
}

Convention convention_arg(int convention) {
  switch (convention) {
    case SB_CONVENTION_SETBOUND: return Convention::Setbound;
    case SB_CONVENTION_CORA: return Convention::Cora;
    default: throw InvalidArgumentError("convention: unknown value " + std::to_string(convention));
  }
}

void bounding_ellipsoid_out(const BoundingEllipsoidEstimator& e, double* P, double* c, double* rho, double* lower,
                            double* upper) {
  if (P != nullptr || rho != nullptr) {
    const Ellipsoid E = e.ellipsoid();
    write_matrix(E.shape(), P);
    if (rho != nullptr) *rho = E.level();
  }
  write_vector(e.center(), c);
  if (lower != nullptr || upper != nullptr) {
    const BoundingBox b = e.bounding_box();
    write_vector(b.lo, lower);
    write_vector(b.hi, upper);
  }
}

}  // namespace

extern "C" {

int sb_enclosing_ellipsoid_shape(int n, int m, const double* G, double* Q) {
  return guard("sb_enclosing_ellipsoid_shape", [&] {
    require_dimension(n, "n");
    require_dimension(m, "m", true);
    require_pointer(Q, "Q");
    write_matrix(enclosing_ellipsoid_shape(matrix_arg(G, n, m, "G")), Q);
  });
}

int sb_bounding_ellipsoid_create(const sb_linear_system* system, const double* QW, const double* QV,
                                 const double* q0, const double* Q0, double rho0, int x0_form, int rule,
                                 int convention, double step_cap, sb_bounding_ellipsoid** out) {
  return guard("sb_bounding_ellipsoid_create", [&] {
    require_pointer(out, "out");
    *out = nullptr;
    const LinearSystem& sys = system_arg(system);
    const int nx = static_cast<int>(sys.nx()), ny = static_cast<int>(sys.ny());
    BoundingEllipsoidOptions opt;
    opt.rule = bounding_rule_arg(rule);
    opt.convention = convention_arg(convention);
    opt.step_cap = step_cap;
    Eigen::MatrixXd W = QW != nullptr ? Eigen::MatrixXd(matrix_arg(QW, nx, nx, "QW")) : Eigen::MatrixXd();
    Eigen::MatrixXd V = QV != nullptr ? Eigen::MatrixXd(matrix_arg(QV, ny, ny, "QV")) : Eigen::MatrixXd();
    Eigen::VectorXd q = vector_arg(q0, nx, "q0");
    Eigen::MatrixXd M = matrix_arg(Q0, nx, nx, "Q0");
    if (x0_form == SB_BE_X0_SHAPE) {
      *out = new sb_bounding_ellipsoid{
          BoundingEllipsoidEstimator(sys, std::move(W), std::move(V), std::move(q), std::move(M), rho0, opt)};
    } else if (x0_form == SB_BE_X0_INVERSE) {
      require_finite(rho0, "rho0");
      require_positive(rho0, "rho0");
      const Ellipsoid x0(std::move(M), std::move(q), rho0);
      *out = new sb_bounding_ellipsoid{BoundingEllipsoidEstimator(sys, std::move(W), std::move(V), x0, opt)};
    } else {
      throw InvalidArgumentError("x0_form: unknown value " + std::to_string(x0_form));
    }
  });
}

int sb_bounding_ellipsoid_free(sb_bounding_ellipsoid* estimator) {
  delete estimator;
  return SB_OK;
}

int sb_bounding_ellipsoid_step(sb_bounding_ellipsoid* estimator, const double* y, const double* u, double* P,
                               double* c, double* rho, double* lower, double* upper) {
  return guard("sb_bounding_ellipsoid_step", [&] {
    require_pointer(estimator, "estimator");
    BoundingEllipsoidEstimator& e = estimator->estimator;
    e.step(vector_arg(y, static_cast<int>(e.system().ny()), "y"),
           vector_arg(u, static_cast<int>(e.system().nu()), "u"));
    bounding_ellipsoid_out(e, P, c, rho, lower, upper);
  });
}

int sb_bounding_ellipsoid_current(const sb_bounding_ellipsoid* estimator, double* P, double* c, double* rho,
                                  double* lower, double* upper) {
  return guard("sb_bounding_ellipsoid_current", [&] {
    require_pointer(estimator, "estimator");
    bounding_ellipsoid_out(estimator->estimator, P, c, rho, lower, upper);
  });
}

int sb_bounding_ellipsoid_shape(const sb_bounding_ellipsoid* estimator, double* Q) {
  return guard("sb_bounding_ellipsoid_shape", [&] {
    require_pointer(estimator, "estimator");
    require_pointer(Q, "Q");
    write_matrix(estimator->estimator.shape(), Q);
  });
}

int sb_bounding_ellipsoid_info(const sb_bounding_ellipsoid* estimator, double* lambda, int* inconsistent,
                               int* steps) {
  return guard("sb_bounding_ellipsoid_info", [&] {
    require_pointer(estimator, "estimator");
    const BoundingEllipsoidEstimator& e = estimator->estimator;
    if (lambda != nullptr) *lambda = e.last_lambda();
    if (inconsistent != nullptr) *inconsistent = e.last_inconsistent() ? 1 : 0;
    if (steps != nullptr) *steps = static_cast<int>(e.steps());
  });
}

int sb_bounding_ellipsoid_noise(const sb_bounding_ellipsoid* estimator, double* QW, double* QV) {
  return guard("sb_bounding_ellipsoid_noise", [&] {
    require_pointer(estimator, "estimator");
    write_matrix(estimator->estimator.QW(), QW);
    write_matrix(estimator->estimator.QV(), QV);
  });
}

int sb_bounding_ellipsoid_reset(sb_bounding_ellipsoid* estimator) {
  return guard("sb_bounding_ellipsoid_reset", [&] {
    require_pointer(estimator, "estimator");
    estimator->estimator.reset();
  });
}

int sb_bounding_ellipsoid_state_size(const sb_bounding_ellipsoid* estimator, int* n) {
  return guard("sb_bounding_ellipsoid_state_size", [&] {
    require_pointer(estimator, "estimator");
    state_size_out(estimator->estimator.save_state(), n);
  });
}

int sb_bounding_ellipsoid_save_state(const sb_bounding_ellipsoid* estimator, double* state, int n) {
  return guard("sb_bounding_ellipsoid_save_state", [&] {
    require_pointer(estimator, "estimator");
    state_copy_out(estimator->estimator.save_state(), state, n);
  });
}

int sb_bounding_ellipsoid_restore_state(sb_bounding_ellipsoid* estimator, const double* state, int n) {
  return guard("sb_bounding_ellipsoid_restore_state", [&] {
    require_pointer(estimator, "estimator");
    estimator->estimator.restore_state(state_arg(state, n));
  });
}

int sb_cora_interval_create(const sb_linear_system* system, const double* c0, int m, const double* G0,
                            const double* L, sb_cora_interval** out) {
  return guard("sb_cora_interval_create", [&] {
    require_pointer(out, "out");
    *out = nullptr;
    const LinearSystem& sys = system_arg(system);
    const int nx = static_cast<int>(sys.nx()), ny = static_cast<int>(sys.ny());
    require_dimension(m, "m", true);
    *out = new sb_cora_interval{CoraIntervalObserver(sys, vector_arg(c0, nx, "c0"), matrix_arg(G0, nx, m, "G0"),
                                                     matrix_arg(L, nx, ny, "L"))};
  });
}

int sb_cora_interval_free(sb_cora_interval* observer) {
  delete observer;
  return SB_OK;
}

int sb_cora_interval_step(sb_cora_interval* observer, const double* y, const double* u, double* lower,
                          double* upper) {
  return guard("sb_cora_interval_step", [&] {
    require_pointer(observer, "observer");
    CoraIntervalObserver& o = observer->observer;
    o.step(vector_arg(y, static_cast<int>(o.system().ny()), "y"), vector_arg(u, static_cast<int>(o.system().nu()), "u"));
    write_vector(o.box().lo, lower);
    write_vector(o.box().hi, upper);
  });
}

int sb_cora_interval_current(const sb_cora_interval* observer, double* lower, double* upper, int* steps) {
  return guard("sb_cora_interval_current", [&] {
    require_pointer(observer, "observer");
    write_vector(observer->observer.box().lo, lower);
    write_vector(observer->observer.box().hi, upper);
    if (steps != nullptr) *steps = static_cast<int>(observer->observer.steps());
  });
}

int sb_cora_interval_reset(sb_cora_interval* observer) {
  return guard("sb_cora_interval_reset", [&] {
    require_pointer(observer, "observer");
    observer->observer.reset();
  });
}

int sb_cora_interval_state_size(const sb_cora_interval* observer, int* n) {
  return guard("sb_cora_interval_state_size", [&] {
    require_pointer(observer, "observer");
    state_size_out(observer->observer.save_state(), n);
  });
}

int sb_cora_interval_save_state(const sb_cora_interval* observer, double* state, int n) {
  return guard("sb_cora_interval_save_state", [&] {
    require_pointer(observer, "observer");
    state_copy_out(observer->observer.save_state(), state, n);
  });
}

int sb_cora_interval_restore_state(sb_cora_interval* observer, const double* state, int n) {
  return guard("sb_cora_interval_restore_state", [&] {
    require_pointer(observer, "observer");
    observer->observer.restore_state(state_arg(state, n));
  });
}

}  // extern "C"
