#include "viscbridge/scene/NetworkTimeStepBound.hpp"
#include "viscbridge/yade/OrderedWetContacts.hpp"
#include "viscbridge/yade/ViscBridgePhys.hpp"
#include "viscbridge/core/timestep/TimeStepBounds.hpp"
#include <core/Scene.hpp>
#include <pkg/common/ElastMat.hpp>
#include <pkg/common/Sphere.hpp>
#include <limits>
#ifdef YADE_OPENMP
#include <omp.h>
#endif

namespace yade {

void NetworkTimeStepBound::evaluate(Scene* sc, bool implicit, Real rayleighFraction)
{
	namespace vb    = viscbridge;
	const Real   inf = std::numeric_limits<Real>::infinity();
	const size_t n   = sc->bodies->size();
	// Per body: the rates summed over its contacts in the order of their ids (OrderedWetContacts), so
	// that the step is the same on any number of threads.
	summed.assign(n * 3, 0);
	orderedWetContacts(sc, [](const Interaction&, const ViscBridgePhys&) { return true; }, contacts);
	for (const auto& [key, I] : contacts) {
		const auto*      ph  = static_cast<const ViscBridgePhys*>(I->phys.get());
		const Body::id_t id1 = I->getId1(), id2 = I->getId2();
		// 1/m_i + 1/m_j = 1/m* (a body that does not move under forces has 1/m = 0 in both):
		// read from the physics, so that the loop touches no body
		const Real mobility = ph->mEff > 0 ? 1 / ph->mEff : 0;
		// P14: springs k_n + 3.5 k_s; contact dashpots 2β√(m*k) likewise; bridge dashpots at S_min.
		// the capillary pull is a spring of stiffness up to capillaryStiffness along n (P22)
		const Real k = ph->kn + 3.5 * ph->ks + (ph->bridge ? ph->capillaryStiffness : 0);
		const Real c = (ph->betan > 0 && ph->kn > 0) ? 2 * std::sqrt(ph->mEff) * (ph->betan * std::sqrt(ph->kn) + 3.5 * ph->betas * std::sqrt(ph->ks)) : 0;
		const Real v = (ph->bridge && !implicit) ? ph->viscousStepCoefficient : 0;
		for (Body::id_t id : { id1, id2 }) {
			summed[3 * id] += k * mobility;
			summed[3 * id + 1] += c * mobility;
			summed[3 * id + 2] += v * mobility;
		}
	}

	// The Rayleigh bound depends on radii and materials only: recomputed when the bodies change.
	const long signature = static_cast<long>(n) * 1000003L + static_cast<long>(sc->materials.size());
	if (signature != rayleighSignature || rayleighFraction != rayleighFractionUsed) {
		rayleigh = inf;
		rayleighBody = -1;
		for (const auto& b : *sc->bodies) {
			if (!b || !b->isDynamic()) continue;
			const auto* sphere = dynamic_cast<const Sphere*>(b->shape.get());
			const auto* mat    = dynamic_cast<const FrictMat*>(b->material.get());
			if (!sphere || !mat) continue;
			const Real t = rayleighFraction * vb::rayleighTime(sphere->radius, mat->density, mat->young, mat->poisson);
			if (t < rayleigh) {
				rayleigh     = t;
				rayleighBody = b->getId();
			}
		}
		rayleighSignature    = signature;
		rayleighFractionUsed = rayleighFraction;
	}

	// Per body: its own limit; the smallest over all bodies (and which body).
	collision = viscous = combined = inf;
	criticalBody                    = -1;
	const long nBodies              = static_cast<long>(n);
#ifdef YADE_OPENMP
#pragma omp parallel
#endif
	{
		Real       myCollision = inf, myViscous = inf, myCombined = inf;
		Body::id_t myCritical  = -1;
#ifdef YADE_OPENMP
#pragma omp for schedule(static) nowait
#endif
		for (long id = 0; id < nBodies; ++id) {
			const shared_ptr<Body>& b = (*sc->bodies)[id];
			if (!b || !b->isDynamic() || !(b->state->mass > 0)) continue;
			const Real stiffness = summed[3 * id], contactDamping = summed[3 * id + 1], damping = summed[3 * id + 2];
			Real own = vb::springLimit(stiffness);
			if (contactDamping > 0) own = vb::networkLimit(contactDamping, stiffness);
			myCollision          = std::min(myCollision, own);
			myViscous            = std::min(myViscous, vb::dashpotLimit(damping));
			const Real bodyBound = std::min(own, vb::networkLimit(contactDamping + damping, stiffness));
			if (bodyBound < myCombined) {
				myCombined = bodyBound;
				myCritical = static_cast<Body::id_t>(id);
			}
		}
#ifdef YADE_OPENMP
#pragma omp critical(viscbridge_stepper_min)
#endif
		{
			collision = std::min(collision, myCollision);
			viscous   = std::min(viscous, myViscous);
			if (myCombined < combined || (myCombined == combined && myCritical >= 0 && (criticalBody < 0 || myCritical < criticalBody))) {
				combined     = myCombined;
				criticalBody = myCritical;
			}
		}
	}
	collision = std::min(collision, rayleigh);
	network   = combined; // P14 alone, before the Rayleigh bound joins
	if (rayleigh < combined) {
		combined     = rayleigh;
		criticalBody = rayleighBody;
	}
}

Real NetworkTimeStepBound::bodyLimit(Body::id_t id, Real extraDamping, Real extraStiffness) const
{
	const Real* r = &summed[3 * id];
	return viscbridge::networkLimit(r[1] + r[2] + extraDamping, r[0] + extraStiffness);
}

} // namespace yade
