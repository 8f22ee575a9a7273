// ViscBridgeImplicitSolver: the preconditioner's life cycle (P15b): which kind, when it is refreshed.
#include "viscbridge/engines/ViscBridgeImplicitSolverGathered.hpp"
#include "viscbridge/core/util/AvailableMemory.hpp"
#include <core/Scene.hpp>
#include <algorithm>

namespace yade {

using namespace implicit_solver;

// The lagged preconditioner, recomputed when the bridges or free components changed, when a refresh
// pays (renewal: the last solve's iterations c_T reach the cycle's average cost per step
// (refreshCost + Σ c_i)/T, which a later refresh could only raise while the iterations grow), or
// when the last solve needed more than refreshIterations iterations.  The Cholesky analysis is kept
// if only the numbers changed.
const vb::Preconditioner* ViscBridgeImplicitSolver::refreshPreconditioner(const vb::ImplicitViscousSystem& sys, const std::vector<long>& pattern)
{
	const std::string kind = sys.size() == 0 ? jacobi : preconditioner == automatic ? automaticKind(sys) : preconditioner;
	if (kind == jacobi) {
		preconditionerInUse = kind;
		factorKind          = "";
		return nullptr;
	}
	if (kind != preconditionerInUse) factorisation.reset();
	preconditionerInUse = kind;
	// The same bodies and bridges: usually in the same order as at the factorisation (YADE reorders its
	// interactions only when some are erased), else the same set once sorted.
	std::vector<long> sorted;
	auto              sortedPattern = [&]() -> const std::vector<long>& {
                if (sorted.empty()) {
                        sorted = pattern;
                        std::sort(sorted.begin(), sorted.end());
                }
                return sorted;
	};
	const bool samePattern = factorisation && factorisation->matches(sys.size()) && (pattern == factorisedOrder || sortedPattern() == factorisedPattern);
	// The multigrid of the same unknowns stays a valid preconditioner when bridges form or rupture (the
	// Cholesky factor's analysis must match the couplings, so it is redone).
	const bool sameUnknowns = samePattern
	        || (kind == multigrid && factorisation && factorisation->matches(sys.size())
	            && std::equal(pattern.begin(), pattern.begin() + sys.bodies().size(), factorisedOrder.begin(), factorisedOrder.begin() + sys.bodies().size()));
	const bool pays = cycleSolves > 0 && static_cast<double>(lastIterationsSeen) * cycleSolves >= refreshCost + cycleIterations;
	// refreshIterations counts beyond what a fresh multigrid needs (tens of iterations; the factor: one or two)
	const int cap = refreshIterations + (kind == multigrid ? freshIterations : 0);
	if (sameUnknowns && !pays && lastIterationsSeen <= cap && factorisedIter >= 0) return factorisation.get();
	if (!refreshLagged(sys, samePattern)) {
		factorisation.reset(); // not positive definite: CG with block Jacobi, then the fallback
		factorisedPattern.clear();
		factorisedOrder.clear();
		preconditionerInUse = jacobi;
		factorKind          = "";
		return nullptr;
	}
	factorisedPattern = sortedPattern();
	factorisedOrder   = pattern;
	factorisedIter    = scene->iter;
	factorBlocks      = static_cast<long>(factorisation->storedBlocks());
	levels            = factorisation->levels();
	factorKind        = factorisation->factorKind();
	refreshCost       = factorisation->refreshCost(sys.bridges().size());
	cycleSolves = cycleIterations = 0;
	++factorisations;
	return factorisation.get();
}

// 'auto' keeps the multigrid it chose while the bed has about the bodies and bridges of that choice
// (within a quarter: a new analysis costs about a factorisation); otherwise it tries the factor.
std::string ViscBridgeImplicitSolver::automaticKind(const vb::ImplicitViscousSystem& sys) const
{
	auto near = [](size_t now, size_t then) { return 4 * std::max(now, then) <= 5 * std::min(now, then); };
	const bool keep = preconditionerInUse == multigrid && factorisation && near(sys.size(), chosenUnknowns) && near(sys.bridges().size(), chosenBridges);
	return keep ? multigrid : cholesky;
}

// The preconditioner of kind preconditionerInUse recomputed; the Cholesky factor analysed first, so
// that 'auto' takes the multigrid instead when the factor would not fit in factorMemoryLimit: the
// factor is the faster of the two at every size measured, 10³–10⁵ bodies, and the solver's peak
// memory was 1.5× its factor's at 10⁵ (docs/performance.md §3).  False: not positive definite.
bool ViscBridgeImplicitSolver::refreshLagged(const vb::ImplicitViscousSystem& sys, bool samePattern)
{
	if (preconditionerInUse == multigrid) {
		if (!factorisation) factorisation = boost::make_shared<vb::LaggedMultigrid>();
		return factorisation->refresh(sys, samePattern);
	}
	if (!factorisation) factorisation = boost::make_shared<vb::LaggedCholesky>();
	auto& factor = static_cast<vb::LaggedCholesky&>(*factorisation);
	factor.analyse(sys, samePattern);
	factorBytes = static_cast<Real>(factor.factorBytes());
	const Real limit = factorMemoryLimit > 0 ? factorMemoryLimit : 0.5 * static_cast<Real>(vb::availableMemoryBytes());
	if (preconditioner != automatic || factorBytes <= limit) return factor.factorise();
	LOG_INFO("preconditioner='auto': the Cholesky factor of " << sys.bodies().size() << " bodies would take " << factorBytes / 1e9 << " GB (limit "
	                                                          << limit / 1e9 << " GB); the multigrid takes its place");
	preconditionerInUse = multigrid;
	chosenUnknowns      = sys.size();
	chosenBridges       = sys.bridges().size();
	factorisation       = boost::make_shared<vb::LaggedMultigrid>();
	return factorisation->refresh(sys, false);
}

} // namespace yade
