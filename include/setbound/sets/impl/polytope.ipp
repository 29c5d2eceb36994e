// setbound — definitions of the functions declared in setbound/sets/polytope.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/sets/polytope.hpp"
#include "setbound/core/config.hpp"

namespace setbound {
namespace detail {

SETBOUND_INLINE QhullFacets qhull_facets(const Eigen::MatrixXd& pts, const std::string& name) {
  const int n = static_cast<int>(pts.rows());
  const int p = static_cast<int>(pts.cols());
  if (n < 2) throw InternalError(name + ": qhull_facets needs dimension >= 2");
  if (p < n + 1) {
    std::ostringstream s;
    s << name << ": " << p << " points cannot span a full-dimensional polytope in R^" << n
      << " (need at least " << n + 1 << ")";
    throw InvalidArgumentError(s.str());
  }
  {  // flat (or single-point) input: Qhull reports it in several ways, some as internal errors
    const Eigen::MatrixXd X = pts.colwise() - pts.rowwise().mean();
    const Eigen::VectorXd ev =
        Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(X * X.transpose(), Eigen::EigenvaluesOnly).eigenvalues();
    if (!(ev(0) > 1e-20 * ev(n - 1)))
      throw InvalidArgumentError(name + ": the points do not span R^" + std::to_string(n) +
                                 " (the polytope would not be full-dimensional)");
  }
  std::vector<double> coords(pts.data(), pts.data() + pts.size());  // column-major = point-major
  char* errbuf = nullptr;
  std::size_t errlen = 0;
  FILE* err = open_memstream(&errbuf, &errlen);
  qhT qh_storage;
  qhT* qh = &qh_storage;
  qh_zero(qh, err);
  char flags[] = "qhull";
  const int code = qh_new_qhull(qh, n, p, coords.data(), False, flags, nullptr, err);
  QhullFacets out;
  if (code == 0) {
    std::vector<char> is_vertex(static_cast<std::size_t>(p), 0);
    vertexT* vertex;
    FORALLvertices {
      const int id = qh_pointid(qh, vertex->point);
      if (id >= 0 && id < p) is_vertex[static_cast<std::size_t>(id)] = 1;
    }
    for (int i = 0; i < p; ++i)
      if (is_vertex[static_cast<std::size_t>(i)]) out.vertex_ids.push_back(i);
    int m = 0;
    facetT* facet;
    FORALLfacets { ++m; }
    out.normals.resize(m, n);
    out.offsets.resize(m);
    out.facet_vertices.resize(static_cast<std::size_t>(m));
    int f = 0;
    FORALLfacets {
      for (int j = 0; j < n; ++j) out.normals(f, j) = facet->normal[j];
      out.offsets(f) = facet->offset;
      vertexT** vertexp;
      FOREACHvertex_(facet->vertices) {
        out.facet_vertices[static_cast<std::size_t>(f)].push_back(qh_pointid(qh, vertex->point));
      }
      ++f;
    }
  }
  qh_freeqhull(qh, !qh_ALL);
  int curlong = 0, totlong = 0;
  qh_memfreeshort(qh, &curlong, &totlong);
  std::fclose(err);
  std::string message = errbuf ? std::string(errbuf, errlen) : std::string();
  std::free(errbuf);
  if (code != 0) {
    if (message.find("QH6154") != std::string::npos || message.find("flat") != std::string::npos ||
        message.find("QH6214") != std::string::npos || message.find("QH6271") != std::string::npos || message.find("QH6421") != std::string::npos)
      throw InvalidArgumentError(name + ": the points do not span R^" + std::to_string(n) +
                                 " (the polytope would not be full-dimensional)");
    const auto cut = message.find('\n');
    throw NumericalError(name + ": Qhull failed (code " + std::to_string(code) + "): " +
                         message.substr(0, cut));
  }
  return out;
}

SETBOUND_INLINE void require_polytope_dim(Eigen::Index got, Eigen::Index want, const std::string& name) {
  if (got != want) {
    std::ostringstream s;
    s << name << ": expected dimension " << want << ", got " << got;
    throw DimensionError(s.str());
  }
}

}  // namespace detail
}  // namespace setbound

namespace setbound {

SETBOUND_INLINE Polytope Polytope::from_vertices(const Eigen::MatrixXd& points, const std::string& name) {
  if (points.rows() < 1) throw DimensionError(name + ": points must have at least one row (n >= 1)");
  require_finite(points, name);
  Polytope P;
  const Eigen::Index n = points.rows();
  if (n == 1) {
    Eigen::Index imin = 0, imax = 0;
    const double lo = points.row(0).minCoeff(&imin);
    const double hi = points.row(0).maxCoeff(&imax);
    if (!(hi > lo))
      throw InvalidArgumentError(name + ": the points do not span R^1 (all equal)");
    P.V_.resize(1, 2);
    P.V_ << lo, hi;
    P.H_.resize(2, 1);
    P.H_ << 1.0, -1.0;
    P.b_.resize(2);
    P.b_ << hi, -lo;
    return P;
  }
  const detail::QhullFacets hull = detail::qhull_facets(points, name);
  P.V_.resize(n, static_cast<Eigen::Index>(hull.vertex_ids.size()));
  for (std::size_t j = 0; j < hull.vertex_ids.size(); ++j)
    P.V_.col(static_cast<Eigen::Index>(j)) = points.col(hull.vertex_ids[j]);
  P.H_ = hull.normals;
  for (Eigen::Index i = 0; i < P.H_.rows(); ++i) P.H_.row(i).normalize();
  // b_i = max over every input point: all of them satisfy H p ≤ b as evaluated.
  P.b_ = (P.H_ * points).rowwise().maxCoeff();
  return P;
}

SETBOUND_INLINE Polytope Polytope::from_halfspaces(const Eigen::MatrixXd& H, const Eigen::VectorXd& b,
                                  const Eigen::VectorXd& interior,
                                  const std::string& name) {
  const Eigen::Index n = H.cols();
  if (n < 1) throw DimensionError(name + ": H must have at least one column");
  if (b.size() != H.rows())
    throw DimensionError(name + ": b has " + std::to_string(b.size()) + " entries but H has " +
                         std::to_string(H.rows()) + " rows");
  detail::require_polytope_dim(interior.size(), n, name + " (interior point)");
  require_finite(H, name + " (H)");
  require_finite(b, name + " (b)");
  require_finite(interior, name + " (interior point)");
  const Eigen::VectorXd slack = b - H * interior;
  for (Eigen::Index i = 0; i < slack.size(); ++i) {
    if (!(slack(i) > 0)) {
      std::ostringstream s;
      s << name << ": the interior point is not strictly inside halfspace " << i
        << " (slack " << slack(i) << ")";
      throw InvalidArgumentError(s.str());
    }
  }
  if (n == 1) {
    double hi = std::numeric_limits<double>::infinity(), lo = -hi;
    for (Eigen::Index i = 0; i < H.rows(); ++i) {
      const double h = H(i, 0);
      if (h > 0) hi = std::min(hi, b(i) / h);
      else if (h < 0) lo = std::max(lo, b(i) / h);
    }
    if (!std::isfinite(lo) || !std::isfinite(hi))
      throw InvalidArgumentError(name + ": the set is unbounded");
    Eigen::MatrixXd pts(1, 2);
    pts << lo, hi;
    return from_vertices(pts, name);
  }
  Eigen::MatrixXd dual(n, H.rows());
  for (Eigen::Index i = 0; i < H.rows(); ++i) dual.col(i) = H.row(i).transpose() / slack(i);
  detail::QhullFacets hull;
  try {
    hull = detail::qhull_facets(dual, name);
  } catch (const InvalidArgumentError&) {
    throw InvalidArgumentError(name + ": the set is unbounded (the normals do not positively span R^" +
                               std::to_string(n) + ")");
  }
  Eigen::MatrixXd verts(n, hull.normals.rows());
  for (Eigen::Index f = 0; f < hull.normals.rows(); ++f) {
    const double off = hull.offsets(f);
    const double scale = std::max(1.0, hull.normals.row(f).cwiseAbs().maxCoeff());
    if (!(off < -1e-12 * scale))
      throw InvalidArgumentError(name + ": the set is unbounded");
    // The facet's active halfspaces: solve them in the least-squares sense (exact vertex when
    // more than n planes meet), starting from the dual facet's hyperplane.
    const auto& ids = hull.facet_vertices[static_cast<std::size_t>(f)];
    Eigen::MatrixXd Ha(static_cast<Eigen::Index>(ids.size()), n);
    Eigen::VectorXd ba(static_cast<Eigen::Index>(ids.size()));
    for (std::size_t r = 0; r < ids.size(); ++r) {
      Ha.row(static_cast<Eigen::Index>(r)) = H.row(ids[r]);
      ba(static_cast<Eigen::Index>(r)) = slack(ids[r]);
    }
    Eigen::VectorXd d = hull.normals.row(f).transpose() / (-off);
    if (Ha.rows() >= n) {
      Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(Ha);
      if (qr.rank() == n) d = qr.solve(ba);
    }
    verts.col(f) = interior + d;
  }
  return from_vertices(verts, name);
}

SETBOUND_INLINE Polytope Polytope::from_box(const Box& box, const std::string& name) {
  check_box(box, name, true);
  const Eigen::Index n = box.size();
  const Eigen::Index p = Eigen::Index(1) << n;
  Eigen::MatrixXd pts(n, p);
  for (Eigen::Index k = 0; k < p; ++k)
    for (Eigen::Index i = 0; i < n; ++i) pts(i, k) = ((k >> i) & 1) ? box.hi()(i) : box.lo()(i);
  return from_vertices(pts, name);
}

SETBOUND_INLINE bool Polytope::contains(const Eigen::Ref<const Eigen::VectorXd>& x, double tol) const {
  detail::require_polytope_dim(x.size(), dimension(), "x");
  return ((H_ * x - b_).array() <= tol).all();
}

SETBOUND_INLINE bool Polytope::contains(const Polytope& other, double tol) const {
  detail::require_polytope_dim(other.dimension(), dimension(), "other");
  return ((H_ * other.V_).colwise() - b_).maxCoeff() <= tol;
}

SETBOUND_INLINE double Polytope::violation(const Eigen::Ref<const Eigen::VectorXd>& x) const {
  detail::require_polytope_dim(x.size(), dimension(), "x");
  return (H_ * x - b_).maxCoeff();
}

SETBOUND_INLINE double Polytope::support(const Eigen::Ref<const Eigen::VectorXd>& d) const {
  detail::require_polytope_dim(d.size(), dimension(), "d");
  return (d.transpose() * V_).maxCoeff();
}

SETBOUND_INLINE Box Polytope::bounding_box() const {
  if (V_.cols() == 0) return Box::empty(0);
  return Box(V_.rowwise().minCoeff(), V_.rowwise().maxCoeff(), "polytope box");
}

SETBOUND_INLINE double Polytope::max_vertex_norm() const { return V_.cols() == 0 ? 0.0 : V_.colwise().norm().maxCoeff(); }

SETBOUND_INLINE Polytope Polytope::linear_map(const Eigen::MatrixXd& M, const std::string& name) const {
  if (M.cols() != dimension())
    throw DimensionError(name + ": expected " + std::to_string(dimension()) + " columns, got " +
                         std::to_string(M.cols()));
  require_finite(M, name);
  return from_vertices(M * V_, name + " (image not full-dimensional: is the matrix singular?)");
}

SETBOUND_INLINE Polytope Polytope::minkowski_sum(const Polytope& other) const {
  detail::require_polytope_dim(other.dimension(), dimension(), "other");
  return from_vertices(pairwise_sums(V_, other.V_), "minkowski sum");
}

SETBOUND_INLINE Polytope Polytope::minkowski_sum_points(const Eigen::MatrixXd& points, const std::string& name) const {
  detail::require_polytope_dim(points.rows(), dimension(), name);
  require_finite(points, name);
  if (points.cols() == 0) throw InvalidArgumentError(name + ": no points (empty set)");
  return from_vertices(pairwise_sums(V_, points), "minkowski sum");
}

SETBOUND_INLINE Polytope Polytope::minkowski_sum(const Box& box) const {
  check_box(box, "box", false);
  detail::require_polytope_dim(box.size(), dimension(), "box");
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(dimension(), dimension());
  G.diagonal() = box.rad();
  return add_segments(box.mid(), G);
}

SETBOUND_INLINE Polytope Polytope::minkowski_sum(const Zonotope& Z) const {
  detail::require_polytope_dim(Z.dimension(), dimension(), "zonotope");
  return add_segments(Z.center(), Z.generators());
}

SETBOUND_INLINE Polytope Polytope::scaled(double a) const {
  if (!(a > 0) || !std::isfinite(a)) {
    std::ostringstream s;
    s << "a: the scaling factor must be finite and > 0, got " << a;
    throw InvalidArgumentError(s.str());
  }
  Polytope P = *this;
  P.V_ *= a;
  P.b_ *= a;
  return P;
}

SETBOUND_INLINE Polytope Polytope::translated(const Eigen::Ref<const Eigen::VectorXd>& t) const {
  detail::require_polytope_dim(t.size(), dimension(), "t");
  require_finite(t, "t");
  Polytope P = *this;
  P.V_.colwise() += t;
  P.b_ += H_ * t;
  // keep every vertex inside the translated H-rep as evaluated
  P.b_ = P.b_.cwiseMax((P.H_ * P.V_).rowwise().maxCoeff());
  return P;
}

SETBOUND_INLINE Eigen::MatrixXd Polytope::pairwise_sums(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B) {
  Eigen::MatrixXd S(A.rows(), A.cols() * B.cols());
  for (Eigen::Index j = 0; j < B.cols(); ++j)
    S.middleCols(j * A.cols(), A.cols()) = A.colwise() + B.col(j);
  return S;
}

SETBOUND_INLINE Polytope Polytope::add_segments(const Eigen::VectorXd& c, const Eigen::MatrixXd& G) const {
  Eigen::MatrixXd V = V_.colwise() + c;
  Polytope P;
  bool first = true;
  for (Eigen::Index j = 0; j < G.cols(); ++j) {
    if (G.col(j).cwiseAbs().maxCoeff() == 0.0) continue;
    Eigen::MatrixXd S(V.rows(), 2 * V.cols());
    S << V.colwise() + G.col(j), V.colwise() - G.col(j);
    P = from_vertices(S, "minkowski sum");
    V = P.V_;
    first = false;
  }
  if (first) return from_vertices(V, "minkowski sum");
  return P;
}

SETBOUND_INLINE void Polytope::check_box(const Box& box, const std::string& name, bool full) {
  if (box.size() < 1) throw DimensionError(name + ": the box has dimension 0");
  if (box.is_empty()) throw InvalidArgumentError(name + ": the box is empty");
  if (!box.lo().allFinite() || !box.hi().allFinite())
    throw InvalidArgumentError(name + ": the box is unbounded");
  if (full && !(box.hi().array() > box.lo().array()).all())
    throw InvalidArgumentError(name + ": the box is degenerate (a zero width)");
}

}  // namespace setbound
