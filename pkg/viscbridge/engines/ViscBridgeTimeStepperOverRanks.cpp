// ViscBridgeTimeStepper under yade.mpy: every rank sees the interactions of its own bodies only, so
// everything the stepper decides on is first combined over the ranks — the bounds (the smallest:
// the owner of a body sees all its interactions, a mirror of it fewer), whether the scene changed,
// the corrections for new bridges, and the described mode — and the mode itself is iterated by all
// ranks together (NetworkOverRanks.hpp).  The ranks then take the same decisions at the same steps
// and set the same dt, the serial one up to rounding; a rank that steps with another dt is an error.
// Every function is a no-op in a serial run.
#include "viscbridge/distributed/Distributed.hpp"
#include "viscbridge/engines/ViscBridgeTimeStepper.hpp"
#include <core/Scene.hpp>

namespace yade {

void ViscBridgeTimeStepper::agreeOnBounds(Scene* sc)
{
	if (!distributed::active(sc)) return;
	const auto combined = distributed::argMin(sc, bound.combined, bound.criticalBody);
	const auto rayleigh = distributed::argMin(sc, bound.rayleigh, bound.rayleighBody);
	const auto network  = distributed::argMin(sc, bound.network, -1);
	const auto coll     = distributed::argMin(sc, bound.collision, -1);
	bound.combined = combined.value, bound.criticalBody = static_cast<Body::id_t>(combined.id);
	bound.rayleigh = rayleigh.value, bound.rayleighBody = static_cast<Body::id_t>(rayleigh.id);
	bound.network = network.value, bound.collision = coll.value;
}

void ViscBridgeTimeStepper::agreeOnChanges(Scene* sc, bool& changed)
{
	if (!distributed::active(sc)) return;
	const std::vector<double> all = distributed::allGather(sc, { double(changed), addedD, addedK, hP14 });
	for (size_t r = 0; r < all.size() / 4; ++r) {
		const double* v = &all[4 * r];
		changed         = changed || v[0] > 0;
		// Weyl's correction is the largest row sum of any rank, P14 the smallest body limit
		addedD = std::max<Real>(addedD, v[1]), addedK = std::max<Real>(addedK, v[2]), hP14 = std::min<Real>(hP14, v[3]);
	}
}

void ViscBridgeTimeStepper::agreeWithOtherRanks(Scene* sc)
{
	if (!distributed::active(sc)) return;
	// the limits are the same on every rank now; the critical body is the one with the largest share
	// of the mode (its owner's), and O.dt must be the same on all of them
	const std::vector<double> all = distributed::allGather(sc, { criticalShare, double(criticalBody), sc->dt });
	const size_t              n   = all.size() / 3;
	std::vector<double>       dts(n);
	size_t                    best = 0;
	for (size_t r = 0; r < n; ++r) {
		if (all[3 * r] > all[3 * best]) best = r; // ties: the lowest rank
		dts[r] = all[3 * r + 2];
	}
	distributed::requireSameDt(sc, dts, "ViscBridgeTimeStepper");
	if (governing != "rayleigh" && all[3 * best] > 0) criticalBody = static_cast<int>(all[3 * best + 1]);
}

} // namespace yade
