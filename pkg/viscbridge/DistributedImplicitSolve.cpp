#include "DistributedImplicitSolve.hpp"
#include "Distributed.hpp"
#include "GhostExchange.hpp"
#include <core/State.hpp>
#include <cmath>

namespace yade {

namespace {
	namespace vb = viscbridge;
	using VecXd  = Eigen::VectorXd;

	// r·z and r·r summed over the ranks (the owned rows of each).
	std::pair<double, double> dotsOverRanks(const Scene* scene, const VecXd& r, const VecXd& z)
	{
		Real rz = r.dot(z), rr = r.squaredNorm();
		distributed::sum(scene, { &rz, &rr });
		return { rz, rr };
	}
}

vb::SolveReport solveOverRanks(const Scene* scene, const vb::ImplicitViscousSystem& sys, const std::vector<Body::id_t>& ids, VecXd& x, double tolerance,
                               int maxIterations, const vb::Preconditioner* pre)
{
	const long  n = static_cast<long>(sys.size());
	const VecXd ghosts = ghostMask(scene, ids);
	VecXd       own = VecXd::Zero(n), prescribed = VecXd::Zero(n);
	const VecXd current = sys.currentVelocities();
	for (long d = 0; d < n; ++d) {
		if (sys.isFree(d)) own[d] = 1;
		else if (ghosts[d] == 0) prescribed[d] = current[d];
	}
	GhostExchange exchange(scene, ids, ghosts);
	// Own rows only: A_oo x_o + A_og x_g = b_o − (Δt D (prescribed + shift))_o, with x_g the owners' x_o.
	VecXd rhs, tmp;
	sys.apply(prescribed, tmp, true);
	rhs      = (sys.rightHandSide() - tmp).cwiseProduct(own);
	VecXd xf = x.cwiseProduct(own);
	exchange.refresh(xf);
	vb::SolveReport rep;
	const double    bnorm = std::sqrt(distributed::sum(scene, rhs.squaredNorm()));
	if (bnorm == 0) {
		x             = prescribed;
		rep.converged = true;
		return rep;
	}
	std::vector<Eigen::LDLT<vb::Mat6>> jacobi;
	if (!pre) jacobi = sys.blockJacobi();
	auto precondition = [&](const VecXd& r, VecXd& z) {
		if (pre && n > 0) {
			pre->apply(r, z);
		} else {
			z.resize(n);
			for (long i = 0; i < n / 6; ++i)
				z.segment<6>(6 * i) = jacobi[i].solve(r.segment<6>(6 * i));
		}
		z = z.cwiseProduct(own);
	};
	VecXd r, z, p, Ap;
	sys.apply(xf, Ap, false);
	r = rhs - Ap.cwiseProduct(own);
	precondition(r, z);
	p = z;
	exchange.refresh(p);
	auto [rz, rr] = dotsOverRanks(scene, r, z);
	for (rep.iterations = 0; rep.iterations < maxIterations; ++rep.iterations) {
		rep.residual = std::sqrt(rr) / bnorm;
		if (rep.residual <= tolerance || !std::isfinite(rep.residual)) break; // global: every rank stops here
		sys.apply(p, Ap, false);
		Ap                 = Ap.cwiseProduct(own);
		const double alpha = rz / distributed::sum(scene, p.dot(Ap));
		xf += alpha * p; // the ghosts' entries follow their owners' exactly (same alpha, same p)
		r -= alpha * Ap;
		precondition(r, z);
		const double rzOld = rz;
		std::tie(rz, rr)   = dotsOverRanks(scene, r, z);
		p                  = z + (rz / rzOld) * p;
		exchange.refresh(p);
	}
	rep.residual = std::sqrt(rr) / bnorm;
	exchange.refresh(xf);
	x             = xf + prescribed;
	rep.converged = distributed::all(scene, x.allFinite()) && std::isfinite(rep.residual) && rep.residual <= tolerance;
	return rep;
}

} // namespace yade
