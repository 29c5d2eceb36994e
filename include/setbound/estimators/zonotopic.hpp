// setbound — the zonotopic estimator structure of papers.md §3.1 (Algorithm 1 of [Le2013]).
//
//   prediction (A known):  p⁺ = A p + B u,  H⁺ = [A H, E]
//   prediction ([A]):      p⁺ = mid[A] p + B u,  H⁺ = [mid[A] H, rs(rad[A]|H|), diag(rad[A]|p|), E]
//   correction, strip by strip (|c_iᵀx + D_i u − y_i| ≤ φ_i, φ_i = Σ_j |F_ij|):
//                          p̂ = p + λ_i (y_i − D_i u − c_iᵀ p),  Ĥ = [(I − λ_i c_iᵀ) H, φ_i λ_i]
//   reduction to at most s generators (Combastel, papers §0.1).
//
// Guarantee: x_k ∈ X̂_k for ANY choice of λ_i ([Le2013] Property 6), because prediction,
// correction and reduction are all outer approximations. The gain rule only changes the size.
// Floating point: the products A p, A H, λ(y − cᵀp) and (I − λcᵀ)H are rounded. Their errors
// are bounded (rounding_radius_*) and collected in one pending box radius r per step, which is
// carried exactly through later corrections ((Z ⊕ B_r) ∩ S ⊆ family(Z) ⊕ κB_r ⊆ family(Z) ⊕
// box(|κ|r), κ = I − λcᵀ) and appended as n generators once per step, before the reduction.
// So the guarantee holds for the sets actually computed; the box is ~1e-15 relative.
//
// Time indexing (identical for every estimator of the library): measurements y_0 … y_{N−1},
// inputs u_0 … u_{N−1}; row k of a trajectory is a set for x_k. step(y_k, u_k) returns the set
// for x_k after using y_k (this family is a filter) and then predicts x_{k+1} with u_k.
// With use_first_measurement = false the first step returns X_0 unchanged, as [Le2013] does.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <limits>
#include <numeric>
#include <string>
#include <vector>

#include "setbound/core/error.hpp"
#include "setbound/core/linear_system.hpp"
#include "setbound/core/validate.hpp"
#include "setbound/sets/strip.hpp"
#include "setbound/sets/zonotope.hpp"

namespace setbound {

namespace rounding_bounds {
inline constexpr double kUnitRoundoff = std::numeric_limits<double>::epsilon() / 2;
/// γ_k = k u / (1 − k u) (Higham), doubled as a safety factor for the additions around it.
inline double gamma(Eigen::Index k) {
  const double ku = static_cast<double>(k + 2) * kUnitRoundoff;
  return 2.0 * ku / (1.0 - ku);
}
}  // namespace rounding_bounds

/// Componentwise bound on the rounding error of computing K p and K H (each column), summed
/// over the generators: the set {fl(Kp) + fl(KH) s + r t} ⊇ {K p + K H s} for this r.
inline Eigen::VectorXd rounding_radius_linear_map(const Eigen::MatrixXd& K, const Zonotope& Z) {
  const Eigen::MatrixXd absK = K.cwiseAbs();
  Eigen::VectorXd mass = Z.center().cwiseAbs();
  if (Z.num_generators() > 0) mass += Z.generators().cwiseAbs().rowwise().sum();
  return rounding_bounds::gamma(K.cols()) * (absK * mass);
}

/// One-strip correction: the output-i row (c, D_i u, φ) of the model and the gain λ.
struct StripMeasurement {
  Strip strip;   // |cᵀx − (y_i − D_i u)| ≤ φ
  Eigen::Index output;
};

/// λ rule: given the set before the strip and the strip, return λ (any λ is guaranteed).
using ZonotopeGainRule = std::function<Eigen::VectorXd(const Zonotope&, const StripMeasurement&)>;

/// [Alamo2005] segment minimisation (papers.md §5.1): λ* = H Hᵀ c / (cᵀ H Hᵀ c + φ²), the
/// minimiser of ‖(I − λcᵀ)H‖_F² + φ²‖λ‖². With nothing to gain (H Hᵀ c = 0) λ = 0.
inline Eigen::VectorXd segment_min_gain(const Zonotope& Z, const StripMeasurement& m) {
  const Eigen::VectorXd& c = m.strip.normal();
  const Eigen::VectorXd g = Z.generators() * (Z.generators().transpose() * c);
  const double phi = m.strip.half_width();
  const double denom = c.dot(g) + phi * phi;
  if (!(denom > 0)) return Eigen::VectorXd::Zero(Z.dimension());
  return g / denom;
}

struct ZonotopicOptions {
  Eigen::Index max_generators = 20;   ///< reduction limit s (>= n_x)
  bool use_first_measurement = true;  ///< intersect X_0 with the strips of y_0 (CORA's loop)
  std::vector<Eigen::Index> strip_order;  ///< order of the outputs; empty = 0, 1, …, n_y − 1
};

/// Sets of one run: row k of center/lower/upper and element k of the lists describe x_k.
struct ZonotopeTrajectory {
  Eigen::MatrixXd center, lower, upper;  ///< N × n_x
  std::vector<Zonotope> sets;
};

class ZonotopicEstimator {
 public:
  ZonotopicEstimator(LinearSystem system, Zonotope x0, ZonotopeGainRule rule, ZonotopicOptions options = {})
      : sys_(std::move(system)), next_(std::move(x0)), rule_(std::move(rule)), opt_(std::move(options)) {
    if (next_.dimension() != sys_.nx())
      throw DimensionError("x0: expected a zonotope of dimension " + std::to_string(sys_.nx()) + ", got " +
                           std::to_string(next_.dimension()));
    if (!rule_) throw InvalidArgumentError("rule: a gain rule is required");
    if (opt_.max_generators < sys_.nx())
      throw InvalidArgumentError("max_generators: must be >= n_x = " + std::to_string(sys_.nx()) + ", got " +
                                 std::to_string(opt_.max_generators));
    if (opt_.strip_order.empty()) {
      opt_.strip_order.resize(static_cast<std::size_t>(sys_.ny()));
      std::iota(opt_.strip_order.begin(), opt_.strip_order.end(), Eigen::Index{0});
    } else {
      std::vector<bool> seen(static_cast<std::size_t>(sys_.ny()), false);
      if (static_cast<Eigen::Index>(opt_.strip_order.size()) != sys_.ny())
        throw InvalidArgumentError("strip_order: must be a permutation of 0..n_y-1");
      for (Eigen::Index i : opt_.strip_order) {
        if (i < 0 || i >= sys_.ny() || seen[static_cast<std::size_t>(i)])
          throw InvalidArgumentError("strip_order: must be a permutation of 0..n_y-1");
        seen[static_cast<std::size_t>(i)] = true;
      }
    }
  }

  const LinearSystem& system() const { return sys_; }
  /// Set for the next state x_{k+1} (before its measurement is used).
  Zonotope prediction() const { return with_rounding_box(next_, pending_); }
  Eigen::Index steps_taken() const { return k_; }

  /// Uses y_k (and u_k for D u_k), returns the set for x_k, then predicts x_{k+1} with u_k.
  /// On any error the estimator is left unchanged.
  Zonotope step(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u) {
    if (y.size() != sys_.ny())
      throw DimensionError("y: expected length " + std::to_string(sys_.ny()) + ", got " + std::to_string(y.size()));
    if (u.size() != sys_.nu())
      throw DimensionError("u: expected length " + std::to_string(sys_.nu()) + ", got " + std::to_string(u.size()));
    require_finite(y, "y");
    require_finite(u, "u");
    Zonotope current = (k_ == 0 && !opt_.use_first_measurement) ? with_rounding_box(next_, pending_)
                                                                 : correct_impl(next_, pending_, y, u);
    Eigen::VectorXd pending(sys_.nx());
    Zonotope predicted = predict_impl(current, u, pending);
    next_ = std::move(predicted);
    pending_ = std::move(pending);
    ++k_;
    return current;
  }

  /// Runs over rows of Y (N × n_y) and U (N × n_u, or empty when n_u = 0).
  ZonotopeTrajectory run(const Eigen::MatrixXd& Y, const Eigen::MatrixXd& U = Eigen::MatrixXd()) {
    const Eigen::Index N = Y.rows();
    if (Y.cols() != sys_.ny())
      throw DimensionError("y: expected " + std::to_string(sys_.ny()) + " columns, got " + std::to_string(Y.cols()));
    if (sys_.nu() > 0) require_shape(U, N, sys_.nu(), "u");
    const Eigen::Index n = sys_.nx();
    ZonotopeTrajectory t{Eigen::MatrixXd(N, n), Eigen::MatrixXd(N, n), Eigen::MatrixXd(N, n), {}};
    t.sets.reserve(static_cast<std::size_t>(N));
    const Eigen::VectorXd no_input(0);
    for (Eigen::Index k = 0; k < N; ++k) {
      Zonotope X = sys_.nu() > 0 ? step(Y.row(k).transpose(), U.row(k).transpose()) : step(Y.row(k).transpose(), no_input);
      const BoundingBox box = X.interval_hull();
      t.center.row(k) = X.center().transpose();
      t.lower.row(k) = box.lo.transpose();
      t.upper.row(k) = box.hi.transpose();
      t.sets.push_back(std::move(X));
    }
    return t;
  }

  /// Strip-by-strip correction (papers §3.1), followed by the reduction.
  Zonotope correct(const Zonotope& X, const Eigen::Ref<const Eigen::VectorXd>& y,
                   const Eigen::Ref<const Eigen::VectorXd>& u) const {
    return correct_impl(X, Eigen::VectorXd::Zero(sys_.nx()), y, u);
  }

  /// Prediction of x_{k+1} from a set for x_k (exact for known A, [Le2013] inclusion for [A]).
  Zonotope predict(const Zonotope& X, const Eigen::Ref<const Eigen::VectorXd>& u) const {
    Eigen::VectorXd r(sys_.nx());
    Zonotope P = predict_impl(X, u, r);
    return with_rounding_box(P, r);
  }

 private:
  /// Correction of X ⊕ box(r): the pending box is carried through every κ_i, the strips'
  /// own rounding is added, and one box is appended before the reduction.
  Zonotope correct_impl(const Zonotope& X, Eigen::VectorXd r, const Eigen::Ref<const Eigen::VectorXd>& y,
                        const Eigen::Ref<const Eigen::VectorXd>& u) const {
    Zonotope Z = X;
    const Eigen::Index n = sys_.nx();
    for (Eigen::Index i : opt_.strip_order) {
      const double yi = y(i) - (sys_.nu() > 0 ? sys_.D().row(i).dot(u) : 0.0);
      StripMeasurement m{Strip(sys_.C().row(i).transpose(), yi, sys_.output_noise_bound(i)), i};
      const Eigen::VectorXd lambda = rule_(Z, m);
      if (lambda.size() != n || !lambda.allFinite())
        throw NumericalError("gain rule: returned a non-finite or wrongly sized lambda for output " +
                             std::to_string(i));
      const Eigen::VectorXd strip_err = rounding_radius_strip(Z, m, lambda);
      Z = Z.intersect_strip_family(m.strip, lambda);
      // |κ| r with κ = I − λcᵀ, rounded up by a relative γ.
      const Eigen::MatrixXd abs_kappa =
          (Eigen::MatrixXd::Identity(n, n) - lambda * m.strip.normal().transpose()).cwiseAbs();
      r = (1.0 + rounding_bounds::gamma(n + 2)) * (abs_kappa * r) + strip_err;
    }
    return reduce(with_rounding_box(Z, r));
  }

  /// Prediction without its rounding box; the rounding radius is returned in r.
  Zonotope predict_impl(const Zonotope& X, const Eigen::Ref<const Eigen::VectorXd>& u, Eigen::VectorXd& r) const {
    Zonotope P = sys_.uncertain_A() ? interval_linear_map(sys_.A(), sys_.A_rad(), X) : X.linear_map(sys_.A());
    r = rounding_radius_linear_map(sys_.A(), X);
    Eigen::VectorXd shift = Eigen::VectorXd::Zero(sys_.nx());
    if (sys_.nu() > 0) {
      shift = sys_.B() * u;
      r += rounding_bounds::gamma(sys_.nu()) * (sys_.B().cwiseAbs() * u.cwiseAbs());
    }
    r += rounding_bounds::gamma(1) * (P.center().cwiseAbs() + shift.cwiseAbs());
    Eigen::MatrixXd H(sys_.nx(), P.num_generators() + sys_.nw());
    H << P.generators(), sys_.E();
    return Zonotope(P.center() + shift, std::move(H)).remove_zero_generators();
  }

  /// Rounding of p̂ = p + λ(y − cᵀp) and Ĥ = H − λ(cᵀH) (papers §0.1 Property 6).
  Eigen::VectorXd rounding_radius_strip(const Zonotope& Z, const StripMeasurement& m,
                                        const Eigen::VectorXd& lambda) const {
    const Eigen::VectorXd& c = m.strip.normal();
    const Eigen::Index n = Z.dimension();
    const double g = rounding_bounds::gamma(n + 2);
    const double innov = std::abs(m.strip.measurement()) + c.cwiseAbs().dot(Z.center().cwiseAbs());
    Eigen::VectorXd r = g * (Z.center().cwiseAbs() + lambda.cwiseAbs() * innov);
    if (Z.num_generators() > 0) {
      const Eigen::MatrixXd absH = Z.generators().cwiseAbs();
      r += g * (absH.rowwise().sum() + lambda.cwiseAbs() * (c.cwiseAbs().transpose() * absH).sum());
    }
    r += g * m.strip.half_width() * lambda.cwiseAbs();
    return r;
  }

  static Zonotope with_rounding_box(const Zonotope& Z, const Eigen::VectorXd& r) {
    const Eigen::Index n = Z.dimension(), m = Z.num_generators();
    Eigen::MatrixXd H(n, m + n);
    H << Z.generators(), Eigen::MatrixXd(r.asDiagonal());
    return Zonotope(Z.center(), std::move(H)).remove_zero_generators();
  }

  Zonotope reduce(const Zonotope& Z) const {
    return Z.num_generators() > opt_.max_generators ? Z.reduce_combastel(opt_.max_generators) : Z;
  }

  LinearSystem sys_;
  Zonotope next_;
  Eigen::VectorXd pending_ = Eigen::VectorXd::Zero(next_.dimension());  ///< rounding box of next_
  ZonotopeGainRule rule_;
  ZonotopicOptions opt_;
  Eigen::Index k_ = 0;
};

}  // namespace setbound
