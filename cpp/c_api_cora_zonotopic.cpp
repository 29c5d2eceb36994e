// setbound — C ABI: CORA's zonotopic observer catalogue on the shared skeleton
// (estimators/zonotopic/observer.hpp).
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "c_api_handles.hpp"
#include "setbound/estimators/zonotopic/designs.hpp"
#include "setbound/estimators/zonotopic/observer.hpp"

using namespace setbound;
using namespace setbound::capi;

struct sb_zono_observer {
  ZonotopicObserver observer;
};

namespace {
// sb_zono_gain_design(_limits) after the guard: the checks of the arguments and the design.
void zono_gain_design_body(const sb_linear_system* system, int method, const lmi::SolverOptions& options,
                           double* gain, double* P, double* Y, double* beta) {
  const LinearSystem& sys = system_arg(system);
  require_pointer(gain, "gain");
  if (method < SB_ZOBS_DESIGN_PRAD_E || method > SB_ZOBS_DESIGN_PRAD_D)
    throw InvalidArgumentError("method: unknown gain design " + std::to_string(method) +
                               " (SB_ZOBS_DESIGN_PRAD_E = 1, SB_ZOBS_DESIGN_NOM_G = 2, SB_ZOBS_DESIGN_PRAD_B = 3, "
                               "SB_ZOBS_DESIGN_PRAD_A = 4, SB_ZOBS_DESIGN_PRAD_C = 5, SB_ZOBS_DESIGN_PRAD_D = 6)");
  const ZonotopicGainDesign d = design_zonotopic_gain(sys, static_cast<ZonotopicGainMethod>(method), options);
  write_matrix(d.gain, gain);
  write_matrix(d.P, P);
  write_matrix(d.Y, Y);
  if (beta) *beta = d.beta;
}
}  // namespace

extern "C" {

int sb_zono_observer_create(const sb_linear_system* system, int rule, const double* gain, int max_generators,
                            int reduction, int convention, int m0, const double* p0, const double* H0,
                            sb_zono_observer** out) {
  return guard("sb_zono_observer_create", [&] {
    require_pointer(out, "out");
    *out = nullptr;
    const LinearSystem& sys = system_arg(system);
    if (rule < SB_ZOBS_SEGMENT_MIN || rule > SB_ZOBS_VOLUME_MIN)
      throw InvalidArgumentError("rule: unknown zonotopic observer rule " + std::to_string(rule) +
                                 " (SB_ZOBS_SEGMENT_MIN = 1 .. SB_ZOBS_VOLUME_MIN = 8)");
    if (convention != SB_CONVENTION_SETBOUND && convention != SB_CONVENTION_CORA)
      throw InvalidArgumentError("convention: expected SB_CONVENTION_SETBOUND (0) or SB_CONVENTION_CORA (1), got " +
                                 std::to_string(convention));
    if (reduction < SB_ZONO_REDUCE_COMBASTEL || reduction > SB_ZONO_REDUCE_PCA)
      throw InvalidArgumentError("reduction: unknown reduction method " + std::to_string(reduction) +
                                 " (SB_ZONO_REDUCE_COMBASTEL = 1, SB_ZONO_REDUCE_GIRARD = 2, SB_ZONO_REDUCE_PCA = 3)");
    if (max_generators > SB_ZONO_MAX_GENERATORS)
      throw InvalidArgumentError("max_generators: at most " + std::to_string(SB_ZONO_MAX_GENERATORS) + ", got " +
                                 std::to_string(max_generators));
    ZonotopicObserverOptions opt;
    opt.rule = static_cast<ZonotopicRule>(rule);
    opt.max_generators = max_generators;
    opt.reduction = static_cast<ZonotopeReduction>(reduction);
    opt.convention = static_cast<Convention>(convention);
    const int nx = static_cast<int>(sys.nx()), ny = static_cast<int>(sys.ny());
    if (needs_gain(opt.rule)) {
      require_pointer(gain, "gain");
      opt.gain = matrix_arg(gain, nx, ny, "gain");
    } else if (gain != nullptr) {
      throw InvalidArgumentError("gain: only the fixed-gain rules take a gain (pass NULL)");
    }
    require_dimension(m0, "m0", true);
    Zonotope x0(vector_arg(p0, nx, "p0"),
                m0 > 0 ? Eigen::MatrixXd(matrix_arg(H0, nx, m0, "H0")) : Eigen::MatrixXd::Zero(nx, 0));
    auto obs = std::make_unique<sb_zono_observer>(sb_zono_observer{ZonotopicObserver(sys, x0, std::move(opt))});
    *out = obs.release();
  });
}

int sb_zono_observer_free(sb_zono_observer* observer) {
  delete observer;
  return SB_OK;
}

int sb_zono_observer_step(sb_zono_observer* observer, const double* y, const double* u, double* center,
                          double* lower, double* upper, int* m) {
  return guard("sb_zono_observer_step", [&] {
    require_pointer(observer, "observer");
    ZonotopicObserver& obs = observer->observer;
    const int nx = static_cast<int>(obs.system().nx()), ny = static_cast<int>(obs.system().ny());
    const int nu = static_cast<int>(obs.system().nu());
    const Eigen::VectorXd yv = vector_arg(y, ny, "y");
    const Eigen::VectorXd uv = nu > 0 ? Eigen::VectorXd(vector_arg(u, nu, "u")) : Eigen::VectorXd(0);
    obs.update(yv, uv);
    if (center) VecMap(center, nx) = obs.current_center();
    if (lower) VecMap(lower, nx) = obs.current_lower();
    if (upper) VecMap(upper, nx) = obs.current_upper();
    if (m) *m = static_cast<int>(obs.current_num_generators());
  });
}

int sb_zono_observer_current_set(const sb_zono_observer* observer, int* m, double* p, double* H) {
  return guard("sb_zono_observer_current_set", [&] {
    require_pointer(observer, "observer");
    require_pointer(m, "m");
    const ZonotopicObserver& obs = observer->observer;
    if (!obs.has_current()) throw InvalidArgumentError("observer: no step has been taken yet");
    const Zonotope z = obs.current_set();
    const int need = static_cast<int>(z.num_generators());
    if (*m < need) {
      const int capacity = *m;
      *m = need;
      throw BufferTooSmallError("m: capacity " + std::to_string(capacity) + " < " + std::to_string(need) +
                                " generators");
    }
    *m = need;
    const int nx = static_cast<int>(obs.system().nx());
    require_pointer(p, "p");
    VecMap(p, nx) = z.center();
    if (need > 0) {
      require_pointer(H, "H");
      RowMap(H, nx, need) = z.generators();
    }
  });
}

int sb_zono_observer_last_gain(const sb_zono_observer* observer, double* gain) {
  return guard("sb_zono_observer_last_gain", [&] {
    require_pointer(observer, "observer");
    require_pointer(gain, "gain");
    const ZonotopicObserver& obs = observer->observer;
    RowMap(gain, obs.system().nx(), obs.system().ny()) = obs.last_gain();
  });
}

int sb_zono_observer_set_inconsistency_policy(sb_zono_observer* observer, int policy) {
  return guard("sb_zono_observer_set_inconsistency_policy", [&] {
    require_pointer(observer, "observer");
    if (policy < SB_ON_INCONSISTENCY_FLAG || policy > SB_ON_INCONSISTENCY_RESET)
      throw InvalidArgumentError("policy: expected SB_ON_INCONSISTENCY_FLAG (0), _RAISE (1) or _RESET (2), got " +
                                 std::to_string(policy));
    observer->observer.set_inconsistency_policy(static_cast<OnInconsistency>(policy));
  });
}

int sb_zono_observer_last_check(const sb_zono_observer* observer, int* status, double* margin, int* reset) {
  return guard("sb_zono_observer_last_check", [&] {
    require_pointer(observer, "observer");
    check_out(observer->observer.last_check(), status, margin, reset);
  });
}

int sb_zono_observer_reset(sb_zono_observer* observer) {
  return guard("sb_zono_observer_reset", [&] {
    require_pointer(observer, "observer");
    observer->observer.reset();
  });
}

int sb_zono_observer_steps(const sb_zono_observer* observer, int* steps) {
  return guard("sb_zono_observer_steps", [&] {
    require_pointer(observer, "observer");
    require_pointer(steps, "steps");
    *steps = static_cast<int>(observer->observer.steps_taken());
  });
}

int sb_zono_observer_state_size(const sb_zono_observer* observer, int* n) {
  return guard("sb_zono_observer_state_size", [&] {
    require_pointer(observer, "observer");
    state_size_out(observer->observer.save_state(), n);
  });
}

int sb_zono_observer_save_state(const sb_zono_observer* observer, double* state, int n) {
  return guard("sb_zono_observer_save_state", [&] {
    require_pointer(observer, "observer");
    state_copy_out(observer->observer.save_state(), state, n);
  });
}

int sb_zono_observer_restore_state(sb_zono_observer* observer, const double* state, int n) {
  return guard("sb_zono_observer_restore_state", [&] {
    require_pointer(observer, "observer");
    observer->observer.restore_state(state_arg(state, n));
  });
}


int sb_zono_gain_design(const sb_linear_system* system, int method, double* gain, double* P, double* Y,
                        double* beta) {
  return guard("sb_zono_gain_design", [&] { zono_gain_design_body(system, method, {}, gain, P, Y, beta); });
}

int sb_zono_gain_design_limits(const sb_linear_system* system, int method, int max_iterations, double time_limit,
                               double* gain, double* P, double* Y, double* beta) {
  return guard("sb_zono_gain_design_limits", [&] {
    if (max_iterations < 0)
      throw InvalidArgumentError("max_iterations: must be > 0 (0 keeps the default, 100), got " + std::to_string(max_iterations));
    if (std::isnan(time_limit)) throw NotFiniteError("time_limit: value is nan; it must be a number");
    if (time_limit < 0)
      throw InvalidArgumentError("time_limit: must be > 0 seconds (0 keeps the default, 30), got " + std::to_string(time_limit));
    lmi::SolverOptions o;
    if (max_iterations > 0) o.max_iterations = max_iterations;
    if (time_limit > 0) o.time_limit = time_limit;
    zono_gain_design_body(system, method, o, gain, P, Y, beta);
  });
}

}  // extern "C"
