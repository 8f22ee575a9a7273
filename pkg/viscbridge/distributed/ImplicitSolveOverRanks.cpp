#include "viscbridge/distributed/ImplicitSolveOverRanks.hpp"
#include "viscbridge/distributed/Distributed.hpp"
#include "viscbridge/distributed/GhostExchange.hpp"
#include <core/State.hpp>
#include <cmath>

namespace yade {

namespace {
	namespace vb = viscbridge;
	using VecXd  = Eigen::VectorXd;

	// CG's sums over the ranks (the owned rows of each) and the ghosts' search direction from their owners.
	struct RankReduction {
		const Scene*   scene;
		GhostExchange& exchange;
		double         sum(double v) const { return distributed::sum(scene, v); }
		void           share(VecXd& p) const { exchange.refresh(p); }
	};
}

vb::SolveReport solveOverRanks(const Scene* scene, const vb::ImplicitViscousSystem& sys, const std::vector<Body::id_t>& ids, VecXd& x, double tolerance,
                               int maxIterations, const vb::Preconditioner* pre)
{
	const VecXd ghosts = ghostMask(scene, ids);
	// Own rows only: A_oo x_o + A_og x_g = b_o − (Δt D (prescribed + shift))_o, with x_g the owners' x_o.
	const vb::ImplicitViscousSystem::FreeProblem f = sys.freeProblem(ghosts);
	GhostExchange                                exchange(scene, ids, ghosts);
	const RankReduction                          reduction { scene, exchange };
	VecXd                                        xf = x.cwiseProduct(f.mask);
	exchange.refresh(xf);
	vb::SolveReport rep;
	const double    bnorm = std::sqrt(reduction.sum(f.rhs.squaredNorm()));
	if (bnorm == 0) {
		x             = f.prescribed;
		rep.converged = true;
		return rep;
	}
	const auto product      = sys.maskedProduct(f.mask, rep);
	const auto precondition = sys.preconditioning(pre, f.mask, rep);
	VecXd      r;
	product(xf, r);
	r = f.rhs - r;
	// the ghosts' entries of x follow their owners' exactly (same alpha, same p)
	vb::conjugateGradients(xf, r, bnorm, tolerance, maxIterations, product, precondition, reduction, rep);
	exchange.refresh(xf);
	x             = xf + f.prescribed;
	rep.converged = distributed::all(scene, x.allFinite()) && std::isfinite(rep.residual) && rep.residual <= tolerance;
	return rep;
}

} // namespace yade
