// setbound — definitions of setbound/estimators/interval/cora_interval_observer.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/estimators/interval/cora_interval_observer.hpp"
#include "setbound/core/config.hpp"

namespace setbound {

SETBOUND_INLINE CoraIntervalObserver::CoraIntervalObserver(LinearSystem sys, Eigen::VectorXd c0, Eigen::MatrixXd G0,
                                                           Eigen::MatrixXd L)
    : sys_(std::move(sys)), c0_(std::move(c0)), G0_(std::move(G0)), L_(std::move(L)) {
  const Eigen::Index n = sys_.nx();
  if (sys_.uncertain_A()) throw InvalidArgumentError("system: an interval A is not supported by CORA's interval observer");
  if (sys_.D().size() > 0 && (sys_.D().array() != 0.0).any())
    throw InvalidArgumentError("system: convention cora: CORA's interval observer has no feedthrough D u (an output "
                               "offset c_V is not part of its recursion); D must be zero");
  detail::require_length(c0_.size(), n, "x0");
  require_finite(c0_, "x0");
  if (G0_.rows() != n) throw DimensionError("x0: generators must have " + std::to_string(n) + " rows");
  require_finite(G0_, "x0");
  require_shape(L_, n, sys_.ny(), "L");
  require_finite(L_, "L");
  Ao_ = sys_.A() - L_ * sys_.C();
  reset();
}

SETBOUND_INLINE void CoraIntervalObserver::reset() {
  const Eigen::Index n = sys_.nx();
  xh_ = c0_;
  cx_ = c0_;
  GX_ = G0_;
  cd_ = Eigen::VectorXd::Zero(n);  // W and V are centred in setbound's form (offsets are inputs)
  GD_ = sys_.E() - L_ * sys_.F();   // (−L)V ⊕ W with ω shared: [G_W, −L G_V] for E = [G_W, 0], F = [0, G_V]
  cs_ = Eigen::VectorXd::Zero(n);
  rs_ = Eigen::VectorXd::Zero(n);
  yprev_.resize(0);
  uprev_.resize(0);
  const Eigen::VectorXd r = G0_.cwiseAbs().rowwise().sum();
  box_ = {c0_ - r, c0_ + r};
  k_ = 0;
}

SETBOUND_INLINE void CoraIntervalObserver::step(const Eigen::Ref<const Eigen::VectorXd>& y,
                                                const Eigen::Ref<const Eigen::VectorXd>& u) {
  detail::require_length(y.size(), sys_.ny(), "y");
  require_finite(y, "y");
  detail::require_length(u.size(), sys_.nu(), "u");
  require_finite(u, "u");
  if (k_ == 0) {
    const Eigen::VectorXd r = G0_.cwiseAbs().rowwise().sum();
    box_ = {c0_ - r, c0_ + r};
  } else {
    // x̂ + □X + S (CORA's R{i+1}, before the update with the previous reading)
    const Eigen::VectorXd c = xh_ + cx_ + cs_;
    const Eigen::VectorXd r = GX_.cwiseAbs().rowwise().sum() + rs_;
    box_ = {c - r, c + r};
    Eigen::VectorXd xn = sys_.A() * xh_ + L_ * (yprev_ - sys_.C() * xh_);
    if (sys_.nu() > 0) xn += sys_.B() * uprev_;
    xh_ = xn;
    cx_ = Ao_ * cx_;
    GX_ = Ao_ * GX_;
    cs_ += cd_;
    rs_ += GD_.cwiseAbs().rowwise().sum();
    cd_ = Ao_ * cd_;
    GD_ = Ao_ * GD_;
  }
  yprev_ = y;
  uprev_ = u;
  ++k_;
}

SETBOUND_INLINE StateFingerprint CoraIntervalObserver::fingerprint() const {
  StateFingerprint f;
  f.add(sys_.A()).add(sys_.B()).add(sys_.C()).add(sys_.E()).add(sys_.F()).add(c0_).add(G0_).add(L_);
  return f;
}

SETBOUND_INLINE std::vector<double> CoraIntervalObserver::save_state() const {
  StateWriter w(StateKind::IntervalHinfObserver, fingerprint());
  w.count(k_).vec(xh_).vec(cx_).mat(GX_).vec(cd_).mat(GD_).vec(cs_).vec(rs_).vec(yprev_).vec(uprev_)
      .vec(box_.lo).vec(box_.hi);
  return w.finish();
}

SETBOUND_INLINE void CoraIntervalObserver::restore_state(const std::vector<double>& state) {
  struct Parsed {
    long long k;
    Eigen::VectorXd xh, cx, cd, cs, rs, yp, up, lo, hi;
    Eigen::MatrixXd GX, GD;
  };
  Parsed t = guard_state_memory(StateKind::IntervalHinfObserver, [&] {
    const Eigen::Index n = sys_.nx();
    StateReader r(state, StateKind::IntervalHinfObserver, fingerprint());
    Parsed p;
    p.k = r.count("steps");
    p.xh = r.vec(n, "estimate");
    p.cx = r.vec(n, "error centre");
    p.GX = r.mat(n, G0_.cols(), "error generators");
    p.cd = r.vec(n, "noise centre");
    p.GD = r.mat(n, sys_.nw(), "noise generators");
    p.cs = r.vec(n, "sum centre");
    p.rs = r.vec(n, "sum radius");
    p.yp = r.vec(p.k > 0 ? sys_.ny() : 0, "previous y");
    p.up = r.vec(p.k > 0 ? sys_.nu() : 0, "previous u");
    p.lo = r.vec(n, "box lower");
    p.hi = r.vec(n, "box upper");
    r.finish();
    return p;
  });
  k_ = static_cast<long>(t.k);
  xh_.swap(t.xh);
  cx_.swap(t.cx);
  GX_.swap(t.GX);
  cd_.swap(t.cd);
  GD_.swap(t.GD);
  cs_.swap(t.cs);
  rs_.swap(t.rs);
  yprev_.swap(t.yp);
  uprev_.swap(t.up);
  box_.lo.swap(t.lo);
  box_.hi.swap(t.hi);
}

}  // namespace setbound
