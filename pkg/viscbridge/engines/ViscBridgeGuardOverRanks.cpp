// ViscBridgeGuard under yade.mpy: what makes its checks global, so that every rank takes the same
// decision at the same step (a rank that went another way would leave the others waiting in a
// collective).  Everything here is a no-op in a serial run.
#include "viscbridge/distributed/Distributed.hpp"
#include "viscbridge/engines/ViscBridgeGuard.hpp"
#include <core/Scene.hpp>

namespace yade {

void ViscBridgeGuard::agreeWithOtherRanks(bool& changed, bool& newRun)
{
	if (!distributed::active(scene)) return;
	// Whether to re-validate, to take a new reference or a rebaseline: if one rank needs it, all do
	// (the signature, the wall-clock test of a new run and the user's rebaseline() are local).  O.dt
	// travels along: a rank stepping with another dt is an error at once.
	const std::vector<double> all
	        = distributed::allGather(scene, { double(changed), double(newRun), double(referencePending), double(rebaselineRequested), scene->dt });
	const size_t        k = 5, n = all.size() / k;
	std::vector<double> dts(n);
	for (size_t r = 0; r < n; ++r) {
		const double* v     = &all[r * k];
		changed             = changed || v[0] > 0;
		newRun              = newRun || v[1] > 0;
		referencePending    = referencePending || v[2] > 0;
		rebaselineRequested = rebaselineRequested || v[3] > 0;
		dts[r]              = v[4];
	}
	distributed::requireSameDt(scene, dts, "ViscBridgeGuard");
}

void ViscBridgeGuard::sumOverRanks(Real& kinetic, Real& gravityWork, Real& work, Real& elastic, bool& finite) const
{
	if (!distributed::active(scene)) return;
	Real nonFinite = finite ? 0 : 1;
	distributed::sum(scene, { &kinetic, &gravityWork, &work, &elastic, &nonFinite });
	finite = nonFinite == 0;
}

int ViscBridgeGuard::distributedCulprit(Body::id_t culprit, Real kinetic) const
{
	if (!distributed::active(scene)) return 0;
	// A rank with a NaN/inf body first (the lowest), else the rank of the most energetic body.
	const shared_ptr<Body>&   b      = culprit >= 0 ? Body::byId(culprit, scene) : Body::byId(0, scene);
	const bool                broken = culprit >= 0 && b && !(b->state->pos.allFinite() && b->state->vel.allFinite() && b->state->angVel.allFinite());
	const std::vector<double> all    = distributed::allGather(scene, { double(broken), culprit >= 0 ? kinetic : -1.0 });
	int                       best   = 0;
	for (size_t r = 0; r < all.size() / 2; ++r) {
		if (all[2 * r] > 0) return static_cast<int>(r);
		if (all[2 * r + 1] > all[2 * best + 1]) best = static_cast<int>(r);
	}
	return best;
}

} // namespace yade
