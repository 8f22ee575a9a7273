#include "viscbridge/scene/NetworkTimeStepBound.hpp"
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
#ifdef YADE_OPENMP
	const int threads = omp_get_max_threads();
#else
	const int threads = 1;
#endif
	// Per-thread sums (3 rates per body), reduced afterwards: the interaction loop runs in parallel
	// without atomics.  Layout: [thread][body][rate].
	rates.assign(static_cast<size_t>(threads) * n * 3, 0);
	summed.assign(n * 3, 0);
	const long nIntr = static_cast<long>(sc->interactions->size());
	const int  vbIndex = ViscBridgePhys::getClassIndexStatic();
#ifdef YADE_OPENMP
#pragma omp parallel for schedule(static)
#endif
	for (long k = 0; k < nIntr; ++k) {
		const Interaction* I = (*sc->interactions)[k].get();
		if (!I->isReal() || I->phys->getClassIndex() != vbIndex) continue;
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
#ifdef YADE_OPENMP
		Real* mine = &rates[static_cast<size_t>(omp_get_thread_num()) * n * 3];
#else
		Real* mine = &rates[0];
#endif
		for (Body::id_t id : { id1, id2 }) {
			mine[3 * id] += k * mobility;
			mine[3 * id + 1] += c * mobility;
			mine[3 * id + 2] += v * mobility;
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
			Real stiffness = 0, contactDamping = 0, damping = 0;
			for (int t = 0; t < threads; ++t) {
				const Real* r = &rates[(static_cast<size_t>(t) * n + id) * 3];
				stiffness += r[0];
				contactDamping += r[1];
				damping += r[2];
			}
			summed[3 * id] = stiffness, summed[3 * id + 1] = contactDamping, summed[3 * id + 2] = damping;
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
