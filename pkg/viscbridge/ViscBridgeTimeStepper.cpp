#include "ViscBridgeTimeStepper.hpp"
#include "Law2_ScGeom_ViscBridgePhys_HertzViscous.hpp"
#include "ViscBridgePhys.hpp"
#include "physics/ModelNames.hpp"
#include "physics/TimeStepBounds.hpp"
#include "physics/Validation.hpp"
#include "SceneValidation.hpp"
#include "Distributed.hpp"
#include <core/InteractionLoop.hpp>
#include <core/Scene.hpp>
#include <pkg/common/ElastMat.hpp>
#include <pkg/common/Sphere.hpp>
#include <limits>
#ifdef YADE_OPENMP
#include <omp.h>
#endif

namespace yade {

CREATE_LOGGER(ViscBridgeTimeStepper);

void ViscBridgeTimeStepper::postLoad(ViscBridgeTimeStepper&)
{
	static const std::string name = "ViscBridgeTimeStepper";
	try {
		viscbridge::requireInRange(name, "safety", safety, 0, true, 1, false);
		viscbridge::requireInRange(name, "maxGrowth", maxGrowth, 1, false, std::numeric_limits<double>::max(), false);
		viscbridge::requireInRange(name, "rayleighFraction", rayleighFraction, 0, true, 1, false);
		viscbridge::requireNonNegative(name, "maxDt", maxDt, " [s]; 0 means no limit");
	} catch (const std::invalid_argument&) {
		safety           = lastValidSafety;
		maxGrowth        = lastValidGrowth;
		rayleighFraction = lastValidRayleigh;
		maxDt            = lastValidMaxDt;
		throw;
	}
	lastValidSafety   = safety;
	lastValidGrowth   = maxGrowth;
	lastValidRayleigh = rayleighFraction;
	lastValidMaxDt    = maxDt;
}

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
		const Real k = ph->kn + 3.5 * ph->ks;
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
	if (rayleigh < combined) {
		combined     = rayleigh;
		criticalBody = rayleighBody;
	}
}

bool ViscBridgeTimeStepper::isActivated()
{
	// the base class divides by timeStepUpdateInterval (an inherited attribute, without a hook on
	// assignment): a value < 1 is reported here, at the first step, instead of a SIGFPE
	if (timeStepUpdateInterval < 1)
		viscbridge::rejectValue("ViscBridgeTimeStepper", "timeStepUpdateInterval", static_cast<double>(timeStepUpdateInterval), ">= 1 (steps)");
	return TimeStepper::isActivated();
}

void ViscBridgeTimeStepper::computeTimeStep(Scene* sc)
{
	const size_t signature = sceneSignature(sc);
	// [MPI] under yade.mpy a rank's invalid body stops every rank (none is left waiting below)
	distributed::collectively(sc, [&] {
		if (signature != validatedSignature) { // e.g. a sphere of radius 0 would give dt = 0 or NaN
			validateScene(sc, false);
			validatedSignature = signature;
		}
	});
	bound.evaluate(sc, viscousIntegrationIsImplicit(sc), rayleighFraction);
	// [MPI] each rank sees its own bodies' interactions: the bound is the minimum over the ranks, and
	// every rank must step from the same dt (checked), so that all of them set the same one
	distributed::reduceTimeStepBound(sc, bound.collision, bound.viscous, bound.combined, bound.criticalBody);
	criticalBody = bound.criticalBody;
	dtCollision  = safety * bound.collision;
	dtViscous    = safety * bound.viscous;
	dtBound      = safety * bound.combined;
	governing    = dtViscous < dtCollision ? "viscous" : "collision";
	Real dt      = dtBound;
	if (maxDt > 0) dt = std::min(dt, maxDt);
	if (!std::isfinite(dt)) return; // nothing to bound (no dynamic spheres, no contacts): keep dt
	if (!(dt > 0))
		throw std::runtime_error("ViscBridgeTimeStepper: the time-step bound is " + viscbridge::formatValue(dt) + " s at body #"
		                         + std::to_string(criticalBody) + "; check its radius, mass and material (all must be > 0 and finite).");
	// growth is limited from a valid previous step only (O.dt <= 0 would otherwise stay there)
	sc->dt = sc->dt > 0 ? std::min(dt, maxGrowth * sc->dt) : dt;
}

} // namespace yade
