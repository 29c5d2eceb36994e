// setbound — C ABI of the LMI solver (setbound.h, section "LMI solver").
#include <memory>
#include <string>
#include <vector>

#include "c_api_common.hpp"
#include "setbound/lmi/classes.hpp"
#include "setbound/lmi/problem.hpp"
#include "setbound/lmi/solver.hpp"

using namespace setbound;

struct sb_lmi_problem {
  lmi::LmiProblem problem;
  lmi::SolverOptions options;
  std::unique_ptr<lmi::InteriorPointSolver> solver;        // reused across solves
  std::unique_ptr<lmi::FeasibilitySolver> feasibility;     // reused across solves
  lmi::SolveResult last;
  bool has_last = false;
  lmi::MarginChecker margin;
  std::uint64_t margin_version = ~std::uint64_t{0};
};

namespace {

sb_lmi_problem* handle(sb_lmi_problem* p) {
  capi::require_pointer(p, "problem");
  return p;
}
const sb_lmi_problem* handle(const sb_lmi_problem* p) {
  capi::require_pointer(p, "problem");
  return p;
}

// Reads F0 (n×n) and Fs (m×n×n, row-major) into a term list (symmetry is checked by the
// problem, which names F0 / Fs[i]).
lmi::BlockTerms read_terms(int m, int n, const double* Fs, const char* name) {
  capi::require_dimension(n, "n");
  if (m > 0 && n > 0) capi::require_pointer(Fs, name);
  lmi::BlockTerms terms;
  terms.reserve(static_cast<size_t>(m));
  for (int i = 0; i < m; ++i) {
    capi::ConstRowMap Fi(Fs + static_cast<size_t>(i) * n * n, n, n);
    terms.emplace_back(i, Eigen::MatrixXd(Fi));
  }
  return terms;
}

void write_result(const lmi::SolveResult& r, sb_lmi_result* out, double* x, int m) {
  out->status = static_cast<int>(r.status);
  out->iterations = r.iterations;
  out->objective = r.objective;
  out->dual_objective = r.dual_objective;
  out->margin = r.margin;
  out->solve_time = r.solve_time;
  out->gap = r.gap;
  out->relative_gap = r.relative_gap;
  out->primal_residual = r.primal_residual;
  out->dual_residual = r.dual_residual;
  if (x != nullptr) {
    for (int i = 0; i < m; ++i) x[i] = i < r.x.size() ? r.x(i) : std::numeric_limits<double>::quiet_NaN();
  }
}

}  // namespace

extern "C" int sb_lmi_problem_create(int num_vars, sb_lmi_problem** out) {
  return capi::guard("sb_lmi_problem_create", [&] {
    capi::require_pointer(out, "out");
    *out = nullptr;
    capi::require_dimension(num_vars, "num_vars");
    // A solve forms the dense num_vars x num_vars Schur complement (32 GiB at 65536): refuse a
    // larger count here with its own message instead of "out of memory" at some later step.
    if (num_vars > SB_LMI_MAX_VARS)
      throw DimensionError("num_vars: at most " + std::to_string(SB_LMI_MAX_VARS) +
                           " variables (the solver's dense Schur complement has num_vars^2 entries), got " +
                           std::to_string(num_vars));
    auto p = std::make_unique<sb_lmi_problem>();
    p->problem.reset(num_vars);
    *out = p.release();
  });
}

extern "C" int sb_lmi_problem_free(sb_lmi_problem* problem) {
  return capi::guard("sb_lmi_problem_free", [&] { delete problem; });
}

extern "C" int sb_lmi_set_objective(sb_lmi_problem* problem, const double* c) {
  return capi::guard("sb_lmi_set_objective", [&] {
    auto* h = handle(problem);
    h->problem.set_objective(capi::vector_arg(c, h->problem.num_vars(), "c"));
  });
}

extern "C" int sb_lmi_add_block(sb_lmi_problem* problem, int n, const double* F0, const double* Fs,
                                int* block_index) {
  return capi::guard("sb_lmi_add_block", [&] {
    auto* h = handle(problem);
    capi::require_dimension(n, "n");
    const auto F0m = capi::matrix_arg(F0, n, n, "F0");
    const int b = h->problem.add_block_terms(F0m, read_terms(h->problem.num_vars(), n, Fs, "Fs"));
    if (block_index != nullptr) *block_index = b;
  });
}

extern "C" int sb_lmi_update_block(sb_lmi_problem* problem, int block, int n, const double* F0,
                                   const double* Fs) {
  return capi::guard("sb_lmi_update_block", [&] {
    auto* h = handle(problem);
    if (block < 0 || block >= h->problem.num_blocks())
      throw InvalidArgumentError("block: index " + std::to_string(block) + " out of range [0, " +
                                 std::to_string(h->problem.num_blocks()) + ")");
    const int size = h->problem.block(block).size;
    if (n != size)
      throw DimensionError("n: block " + std::to_string(block) + " has size " + std::to_string(size) +
                           ", got " + std::to_string(n));
    const auto F0m = capi::matrix_arg(F0, n, n, "F0");
    h->problem.update_block_terms(block, F0m, read_terms(h->problem.num_vars(), n, Fs, "Fs"));
  });
}

extern "C" int sb_lmi_set_logdet(sb_lmi_problem* problem, int n, const double* G0, const double* Gs) {
  return capi::guard("sb_lmi_set_logdet", [&] {
    auto* h = handle(problem);
    capi::require_dimension(n, "n", true);
    if (n == 0) {
      h->problem.clear_logdet();
      return;
    }
    const auto G0m = capi::matrix_arg(G0, n, n, "G0");
    h->problem.set_logdet_terms(G0m, read_terms(h->problem.num_vars(), n, Gs, "Gs"));
  });
}

extern "C" int sb_lmi_set_equalities(sb_lmi_problem* problem, int rows, const double* Aeq, const double* beq) {
  return capi::guard("sb_lmi_set_equalities", [&] {
    auto* h = handle(problem);
    capi::require_dimension(rows, "rows", true);
    const auto A = capi::matrix_arg(Aeq, rows, h->problem.num_vars(), "Aeq");
    const auto b = capi::vector_arg(beq, rows, "beq");
    h->problem.set_equalities(Eigen::MatrixXd(A), b);
  });
}

extern "C" int sb_lmi_set_options(sb_lmi_problem* problem, int max_iterations, double gap_rel, double feas,
                                  double time_limit) {
  return capi::guard("sb_lmi_set_options", [&] {
    auto* h = handle(problem);
    for (auto [v, name] : {std::pair{gap_rel, "gap_rel"}, {feas, "feas"}, {time_limit, "time_limit"}})
      if (std::isnan(v)) throw NotFiniteError(std::string(name) + ": value is nan; it must be a number");
    lmi::SolverOptions o;
    if (max_iterations > 0) o.max_iterations = max_iterations;
    if (gap_rel > 0) {
      o.gap_rel = gap_rel;
      o.reduced_gap_rel = std::max(o.reduced_gap_rel, 10 * gap_rel);
    }
    if (feas > 0) {
      o.feas = feas;
      o.reduced_feas = std::max(o.reduced_feas, 10 * feas);
    }
    if (time_limit > 0) o.time_limit = time_limit;
    o.threads = h->options.threads;  // set by sb_lmi_set_threads
    o.validate();
    h->options = o;
    if (h->solver) h->solver->set_options(o);
    h->feasibility.reset();
  });
}

extern "C" int sb_lmi_set_threads(sb_lmi_problem* problem, int threads) {
  return capi::guard("sb_lmi_set_threads", [&] {
    auto* h = handle(problem);
    lmi::SolverOptions o = h->options;
    o.threads = threads;
    o.validate();
    h->options = o;
    if (h->solver) h->solver->set_options(o);
    h->feasibility.reset();
  });
}

extern "C" int sb_lmi_threads_available(void) {
#if defined(_OPENMP)
  return 1;
#else
  return 0;
#endif
}

extern "C" int sb_lmi_problem_size(const sb_lmi_problem* problem, int* num_vars, int* num_blocks) {
  return capi::guard("sb_lmi_problem_size", [&] {
    const auto* h = handle(problem);
    if (num_vars != nullptr) *num_vars = h->problem.num_vars();
    if (num_blocks != nullptr) *num_blocks = h->problem.num_blocks();
  });
}

static void solve_impl(sb_lmi_problem* h, int problem_class, sb_lmi_result* result, double* x) {
  capi::require_pointer(result, "result");
  h->problem.require_solvable();
  if (problem_class == SB_LMI_CLASS_FEASIBILITY) {
    if (!h->feasibility) h->feasibility = std::make_unique<lmi::FeasibilitySolver>(h->problem, h->options);
    h->last = h->feasibility->solve();
  } else if (problem_class == SB_LMI_CLASS_AUTO) {
    if (h->problem.has_logdet()) {
      h->last = lmi::solve_maxdet(h->problem, h->options);
    } else {
      if (h->problem.num_blocks() == 0)
        throw InvalidArgumentError("blocks: the problem has no LMI block (add at least one)");
      if (!h->solver) h->solver = std::make_unique<lmi::InteriorPointSolver>(h->problem, h->options);
      const lmi::SolveResult& r = h->solver->solve();
      // Copy only into preallocated storage (same shapes after the first solve).
      h->last.status = r.status;
      h->last.iterations = r.iterations;
      h->last.objective = r.objective;
      h->last.dual_objective = r.dual_objective;
      h->last.gap = r.gap;
      h->last.relative_gap = r.relative_gap;
      h->last.primal_residual = r.primal_residual;
      h->last.dual_residual = r.dual_residual;
      h->last.margin = r.margin;
      h->last.solve_time = r.solve_time;
      h->last.x = r.x;
      h->last.y = r.y;
      h->last.Z = r.Z;
    }
  } else {
    throw InvalidArgumentError("problem_class: unknown value " + std::to_string(problem_class));
  }
  h->has_last = true;
  write_result(h->last, result, x, h->problem.num_vars());
}

extern "C" int sb_lmi_solve(sb_lmi_problem* problem, sb_lmi_result* result, double* x) {
  return capi::guard("sb_lmi_solve", [&] { solve_impl(handle(problem), SB_LMI_CLASS_AUTO, result, x); });
}

extern "C" int sb_lmi_solve_class(sb_lmi_problem* problem, int problem_class, sb_lmi_result* result, double* x) {
  return capi::guard("sb_lmi_solve_class", [&] { solve_impl(handle(problem), problem_class, result, x); });
}

extern "C" int sb_lmi_dual(const sb_lmi_problem* problem, int block, double* Z) {
  return capi::guard("sb_lmi_dual", [&] {
    const auto* h = handle(problem);
    if (!h->has_last) throw InvalidArgumentError("problem: not solved yet");
    if (block < 0 || block >= static_cast<int>(h->last.Z.size()))
      throw InvalidArgumentError("block: index " + std::to_string(block) + " out of range");
    capi::require_pointer(Z, "Z");
    const Eigen::MatrixXd& D = h->last.Z[static_cast<size_t>(block)];
    capi::RowMap(Z, D.rows(), D.cols()) = D;
  });
}

extern "C" int sb_lmi_dual_eq(const sb_lmi_problem* problem, double* y) {
  return capi::guard("sb_lmi_dual_eq", [&] {
    const auto* h = handle(problem);
    if (!h->has_last) throw InvalidArgumentError("problem: not solved yet");
    const Eigen::Index p = h->last.y.size();
    if (p == 0) return;
    capi::require_pointer(y, "y");
    capi::VecMap(y, p) = h->last.y;
  });
}

extern "C" int sb_lmi_margin(const sb_lmi_problem* problem, const double* x, double* margin) {
  return capi::guard("sb_lmi_margin", [&] {
    auto* h = const_cast<sb_lmi_problem*>(handle(problem));
    capi::require_pointer(margin, "margin");
    const Eigen::VectorXd xv = capi::vector_arg(x, h->problem.num_vars(), "x");
    require_finite(xv, "x");
    if (h->margin_version != h->problem.structure_version()) {
      h->margin.setup(h->problem);
      h->margin_version = h->problem.structure_version();
    }
    *margin = h->margin.margin(h->problem, xv);
  });
}

extern "C" int sb_lmi_solve_gevp(sb_lmi_problem* problem, int n, const double* A0, const double* As,
                                 const double* B0, const double* Bs, double lambda_lo, double lambda_hi,
                                 double tol, sb_lmi_result* result, double* lambda, double* x) {
  return capi::guard("sb_lmi_solve_gevp", [&] {
    auto* h = handle(problem);
    capi::require_pointer(result, "result");
    capi::require_pointer(lambda, "lambda");
    capi::require_dimension(n, "n");
    require_finite(lambda_lo, "lambda_lo");
    require_finite(lambda_hi, "lambda_hi");
    require_positive(tol, "tol");
    const int m = h->problem.num_vars();
    const Eigen::MatrixXd A0m = capi::matrix_arg(A0, n, n, "A0");
    const Eigen::MatrixXd B0m = capi::matrix_arg(B0, n, n, "B0");
    for (auto [M, name] : {std::pair{&A0m, "A0"}, {&B0m, "B0"}}) {
      require_finite(*M, name);
      require_symmetric(*M, name);
    }
    lmi::BlockTerms At = read_terms(m, n, As, "As"), Bt = read_terms(m, n, Bs, "Bs");
    for (size_t i = 0; i < At.size(); ++i) {
      require_finite(At[i].second, "As[" + std::to_string(i) + "]");
      require_symmetric(At[i].second, "As[" + std::to_string(i) + "]");
      require_finite(Bt[i].second, "Bs[" + std::to_string(i) + "]");
      require_symmetric(Bt[i].second, "Bs[" + std::to_string(i) + "]");
    }
    lmi::GevpOptions go;
    go.lambda_lo = lambda_lo;
    go.lambda_hi = lambda_hi;
    go.tol = tol;
    go.solver = h->options;
    const lmi::GevpResult g = lmi::solve_gevp(h->problem, A0m, At, B0m, Bt, go);
    lmi::SolveResult r;
    r.status = g.status;
    r.iterations = g.iterations;
    r.objective = g.lambda;
    r.dual_objective = g.lower;
    r.margin = g.margin;
    r.solve_time = g.solve_time;
    r.gap = g.lambda - g.lower;
    r.relative_gap = r.gap / std::max(1.0, std::abs(g.lambda));
    r.primal_residual = 0;
    r.dual_residual = 0;
    r.x = g.x.size() == m ? g.x : Eigen::VectorXd::Constant(m, std::numeric_limits<double>::quiet_NaN());
    *lambda = g.lambda;
    write_result(r, result, x, m);
  });
}
