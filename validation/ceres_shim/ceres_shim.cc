// ceres_shim.cc -- extern "C" wrapper over Ceres' C++ API: bounded parameters and a silent
// solve (ceres_shim.h). Kept to exactly what validation/src/fit_envelope.c uses.
#include "ceres_shim.h"

#include <ceres/ceres.h>
#include <glog/logging.h>

#include <cmath>
#include <cstring>
#include <mutex>
#include <vector>

namespace {

class CallbackCost : public ceres::CostFunction {
public:
  CallbackCost(int np, int nres, val_ceres_cost_t cost, void *user) : cost_(cost), user_(user) {
    set_num_residuals(nres);
    mutable_parameter_block_sizes()->push_back(np);
  }

  bool Evaluate(double const *const *parameters, double *residuals,
                double **jacobians) const override {
    double *jac = (jacobians != nullptr && jacobians[0] != nullptr) ? jacobians[0] : nullptr;
    return cost_(user_, parameters[0], residuals, jac) != 0;
  }

private: // the sizes live in the base class (num_residuals(), parameter_block_sizes())
  val_ceres_cost_t cost_;
  void *user_;
};

// glog without InitGoogleLogging() writes warnings to stderr; a verification run must stay
// quiet, so only fatal messages (which abort anyway) are let through.
// Once per process, also when solves run on several threads at a time.
void silence_logging() {
  static std::once_flag once;
  std::call_once(once, [] {
    FLAGS_minloglevel = google::GLOG_FATAL;
    FLAGS_stderrthreshold = google::GLOG_FATAL;
  });
}

// One bounded solve; `fixed` parameters are held constant (a SubsetManifold).
void solve_once(int np, double *p, const double *lower, const double *upper, int nres,
                val_ceres_cost_t cost, void *user, const val_ceres_options_t *opt,
                const std::vector<int> &fixed, ceres::Solver::Summary *s) {
  ceres::Problem::Options popt;
  popt.cost_function_ownership = ceres::TAKE_OWNERSHIP;
  popt.manifold_ownership = ceres::TAKE_OWNERSHIP;
  ceres::Problem problem(popt);
  problem.AddResidualBlock(new CallbackCost(np, nres, cost, user), nullptr, p);
  for (int j = 0; j < np; j++) {
    if (lower != nullptr && std::isfinite(lower[j]))
      problem.SetParameterLowerBound(p, j, lower[j]);
    if (upper != nullptr && std::isfinite(upper[j]))
      problem.SetParameterUpperBound(p, j, upper[j]);
  }
  if (static_cast<int>(fixed.size()) == np)
    problem.SetParameterBlockConstant(p);
  else if (!fixed.empty())
    problem.SetManifold(p, new ceres::SubsetManifold(np, fixed));
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_QR;
  so.minimizer_progress_to_stdout = false;
  so.logging_type = ceres::SILENT;
  so.num_threads = 1;
  if (opt != nullptr) {
    if (opt->max_iterations > 0)
      so.max_num_iterations = opt->max_iterations;
    if (opt->function_tolerance > 0)
      so.function_tolerance = opt->function_tolerance;
    if (opt->gradient_tolerance > 0)
      so.gradient_tolerance = opt->gradient_tolerance;
    if (opt->parameter_tolerance > 0)
      so.parameter_tolerance = opt->parameter_tolerance;
  }
  ceres::Solve(so, &problem, s);
}

// Gradient of 1/2 |r|^2 at p from the callback (J^t r).
bool gradient(int np, const double *p, int nres, val_ceres_cost_t cost, void *user,
              std::vector<double> *g) {
  std::vector<double> r(nres), jac(static_cast<size_t>(nres) * np);
  if (!cost(user, p, r.data(), jac.data()))
    return false;
  g->assign(np, 0.0);
  for (int i = 0; i < nres; i++)
    for (int j = 0; j < np; j++)
      (*g)[j] += jac[static_cast<size_t>(i) * np + j] * r[i];
  return true;
}

} // namespace

extern "C" int val_ceres_solve_bounded(int np, double *p, const double *lower, const double *upper,
                                       int nres, val_ceres_cost_t cost, void *user,
                                       const val_ceres_options_t *opt,
                                       val_ceres_summary_t *summary) {
  if (np <= 0 || nres <= 0 || p == nullptr || cost == nullptr || summary == nullptr)
    return -1;
  silence_logging();
  // Ceres bounds are enforced by projecting the trust-region step, which can creep along an
  // active bound for many iterations without reaching the optimum (a 2-parameter line fit with
  // one slope at its bound stalls at cost 4.18 instead of 4). An active-set outer loop fixes
  // that: parameters sitting at a bound with the gradient pushing outwards are held constant
  // and the rest re-solved, until the active set no longer changes (KKT conditions hold).
  std::vector<int> fixed;
  ceres::Solver::Summary s;
  double initial_cost = -1.0;
  int iterations = 0;
  for (int outer = 0; outer < 2 * np + 2; outer++) {
    solve_once(np, p, lower, upper, nres, cost, user, opt, fixed, &s);
    if (initial_cost < 0)
      initial_cost = s.initial_cost;
    iterations += static_cast<int>(s.iterations.size());
    if (!s.IsSolutionUsable())
      break;
    std::vector<double> g;
    if (!gradient(np, p, nres, cost, user, &g))
      break;
    std::vector<int> active;
    for (int j = 0; j < np; j++) {
      double tol_lo = lower ? 1e-12 * (1.0 + std::fabs(lower[j])) : 0.0;
      double tol_hi = upper ? 1e-12 * (1.0 + std::fabs(upper[j])) : 0.0;
      bool at_lo = lower != nullptr && std::isfinite(lower[j]) && p[j] <= lower[j] + tol_lo;
      bool at_hi = upper != nullptr && std::isfinite(upper[j]) && p[j] >= upper[j] - tol_hi;
      if ((at_lo && g[j] >= 0.0) || (at_hi && g[j] <= 0.0))
        active.push_back(j);
    }
    if (active == fixed)
      break;
    fixed = active;
  }
  *summary = {}; /* value-initialised: every field zero */
  summary->converged = s.termination_type == ceres::CONVERGENCE;
  summary->usable = s.IsSolutionUsable();
  summary->iterations = iterations;
  summary->initial_cost = initial_cost;
  summary->final_cost = s.final_cost;
  std::strncpy(summary->message, s.message.c_str(), sizeof summary->message - 1);
  return 0;
}
