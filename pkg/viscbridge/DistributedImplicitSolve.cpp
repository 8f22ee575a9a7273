#include "DistributedImplicitSolve.hpp"
#include "Distributed.hpp"
#include <core/State.hpp>
#include <cmath>

namespace yade {

namespace {
	namespace vb = viscbridge;
	using VecXd  = Eigen::VectorXd;

	// Which unknowns of this rank's system are ghosts: the free components of the bodies other
	// workers own (as free there: dynamic, with a mass, not blocked).  The master's bodies are
	// boundary conditions, as in mpy, which never sends their states.
	VecXd ghostMask(const Scene* scene, const std::vector<Body::id_t>& ids)
	{
		const auto own = distributed::ownership(scene);
		VecXd      mask = VecXd::Zero(6 * static_cast<long>(ids.size()));
		for (size_t i = 0; i < ids.size(); ++i) {
			const Body& b = *(*scene->bodies)[ids[i]];
			if (own.body(b) || b.subdomain == 0 || !b.isDynamic() || !(b.state->mass > 0)) continue;
			for (int d = 0; d < 6; ++d)
				mask[6 * i + d] = (b.state->blockedDOFs & State::axisDOF(d % 3, d >= 3)) ? 0 : 1;
		}
		return mask;
	}

	// Refreshes the ghost entries of a vector from their owners (who send their own entries).
	class GhostExchange {
	public:
		GhostExchange(const Scene* scene, const std::vector<Body::id_t>& ids, const VecXd& ghosts)
		        : scene_(scene)
		        , halo_(distributed::halo(scene))
		        , ghosts_(ghosts)
		{
			std::vector<int> index(scene->bodies->size(), -1);
			for (size_t i = 0; i < ids.size(); ++i)
				index[ids[i]] = static_cast<int>(i);
			auto at = [&](const std::vector<Body::id_t>& list) {
				std::vector<int> out;
				for (const Body::id_t id : list)
					out.push_back(id >= 0 && static_cast<size_t>(id) < index.size() ? index[id] : -1);
				return out;
			};
			for (size_t j = 0; j < halo_.ranks.size(); ++j) {
				sendAt_.push_back(at(halo_.sent[j]));
				receiveAt_.push_back(at(halo_.received[j]));
				send_.emplace_back(6 * halo_.sent[j].size(), 0.0);
				received_.emplace_back(6 * halo_.received[j].size(), 0.0);
			}
		}

		void refresh(VecXd& v)
		{
			for (size_t j = 0; j < sendAt_.size(); ++j)
				for (size_t k = 0; k < sendAt_[j].size(); ++k) {
					const int i = sendAt_[j][k];
					for (int d = 0; d < 6; ++d) // a body without bridges here has none on its neighbours either
						send_[j][6 * k + d] = i >= 0 ? v[6 * i + d] : 0.0;
				}
			distributed::exchange(scene_, halo_, send_, received_);
			for (size_t j = 0; j < receiveAt_.size(); ++j)
				for (size_t k = 0; k < receiveAt_[j].size(); ++k) {
					const int i = receiveAt_[j][k];
					if (i < 0) continue;
					for (int d = 0; d < 6; ++d)
						if (ghosts_[6 * i + d] != 0) v[6 * i + d] = received_[j][6 * k + d];
				}
		}

	private:
		const Scene*                     scene_;
		distributed::Halo                halo_;
		const VecXd&                     ghosts_;
		std::vector<std::vector<int>>    sendAt_, receiveAt_;
		std::vector<std::vector<double>> send_, received_;
	};

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
