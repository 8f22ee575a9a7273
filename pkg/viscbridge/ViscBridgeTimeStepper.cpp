#include "ViscBridgeTimeStepper.hpp"
#include "Law2_ScGeom_ViscBridgePhys_HertzViscous.hpp"
#include "ViscBridgePhys.hpp"
#include "physics/ModelNames.hpp"
#include "physics/TimeStepBounds.hpp"
#include "physics/Validation.hpp"
#include <core/InteractionLoop.hpp>
#include <core/Scene.hpp>
#include <pkg/common/ElastMat.hpp>
#include <pkg/common/Sphere.hpp>
#include <limits>

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

bool viscousIntegrationIsImplicit(const Scene* sc)
{
	for (const auto& e : sc->engines) {
		const auto* loop = dynamic_cast<const InteractionLoop*>(e.get());
		if (!loop) continue;
		for (const auto& f : loop->lawDispatcher->functors) {
			const auto* law = dynamic_cast<const Law2_ScGeom_ViscBridgePhys_HertzViscous*>(f.get());
			if (law && law->integrationIndex == static_cast<int>(viscbridge::Integration::implicitEuler)) return true;
		}
	}
	return false;
}

void NetworkTimeStepBound::evaluate(Scene* sc, bool implicit, Real rayleighFraction)
{
	namespace vb   = viscbridge;
	const Real   inf = std::numeric_limits<Real>::infinity();
	const size_t n   = sc->bodies->size();
	damping.assign(n, 0);
	contactDamping.assign(n, 0);
	stiffness.assign(n, 0);

	auto inverseMass = [](const Body& b) { return (b.isDynamic() && b.state->mass > 0) ? 1 / b.state->mass : Real(0); };
	for (const auto& I : *sc->interactions) {
		if (!I->isReal()) continue;
		const auto* ph = dynamic_cast<const ViscBridgePhys*>(I->phys.get());
		if (!ph) continue;
		const Body::id_t id1 = I->getId1(), id2 = I->getId2();
		const Real       mobility = inverseMass(*Body::byId(id1, sc)) + inverseMass(*Body::byId(id2, sc));
		// P14: springs k_n + 3.5 k_s; contact dashpots 2β√(m*k) likewise; bridge dashpots at S_min.
		const Real k = ph->kn + 3.5 * ph->ks;
		const Real c = (ph->betan > 0 && ph->kn > 0) ? 2 * std::sqrt(ph->mEff) * (ph->betan * std::sqrt(ph->kn) + 3.5 * ph->betas * std::sqrt(ph->ks)) : 0;
		const Real v = (ph->bridge && !implicit) ? ph->viscousStepCoefficient : 0;
		for (Body::id_t id : { id1, id2 }) {
			stiffness[id] += k * mobility;
			contactDamping[id] += c * mobility;
			damping[id] += v * mobility;
		}
	}

	collision = viscous = combined = inf;
	criticalBody                    = -1;
	for (const auto& b : *sc->bodies) {
		if (!b || !b->isDynamic() || !(b->state->mass > 0)) continue;
		const Body::id_t id  = b->getId();
		Real             own = vb::springLimit(stiffness[id]);
		if (contactDamping[id] > 0) own = vb::networkLimit(contactDamping[id], stiffness[id]);
		const auto* sphere = dynamic_cast<const Sphere*>(b->shape.get());
		const auto* mat    = dynamic_cast<const FrictMat*>(b->material.get());
		if (sphere && mat) own = std::min(own, rayleighFraction * vb::rayleighTime(sphere->radius, mat->density, mat->young, mat->poisson));
		collision            = std::min(collision, own);
		viscous              = std::min(viscous, vb::dashpotLimit(damping[id]));
		const Real bodyBound = std::min(own, vb::networkLimit(contactDamping[id] + damping[id], stiffness[id]));
		if (bodyBound < combined) {
			combined     = bodyBound;
			criticalBody = id;
		}
	}
}

void ViscBridgeTimeStepper::computeTimeStep(Scene* sc)
{
	bound.evaluate(sc, viscousIntegrationIsImplicit(sc), rayleighFraction);
	criticalBody = bound.criticalBody;
	dtCollision  = safety * bound.collision;
	dtViscous    = safety * bound.viscous;
	dtBound      = safety * bound.combined;
	governing    = dtViscous < dtCollision ? "viscous" : "collision";
	Real dt      = dtBound;
	if (maxDt > 0) dt = std::min(dt, maxDt);
	if (!std::isfinite(dt)) return; // nothing to bound (no dynamic spheres, no contacts): keep dt
	sc->dt = std::min(dt, maxGrowth * sc->dt);
}

} // namespace yade
