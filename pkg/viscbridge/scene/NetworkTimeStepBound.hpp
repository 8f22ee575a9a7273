// P14 (physics.md §3) over the live interactions: the rigorous, sufficient bound of the explicit
// scheme, per body, and the collision bound of the spheres' Rayleigh time.
#pragma once
#include <core/Body.hpp>
#include <core/Scene.hpp>
#include "viscbridge/yade/ContactForce.hpp"
#include <vector>

namespace yade {

// P14 over the live interactions (without the safety factor); see ViscBridgeTimeStepper.
struct NetworkTimeStepBound {
	Real       collision = 0, viscous = 0, combined = 0; // [s], inf when nothing bounds them
	Real       network = 0;                              // P14 of the interactions alone [s]
	Body::id_t criticalBody = -1;
	// the contacts in the order of their bodies' ids, kept to be reused between calls
	OrderedContacts contacts;
	// the smallest rayleighFraction × T_R over the spheres, cached while the bodies stay the same
	Real       rayleigh = 0, rayleighFractionUsed = -1;
	Body::id_t rayleighBody = -1;
	long       rayleighSignature = -1;
	std::vector<Real> summed; // per body: stiffness, contact damping and bridge damping rates of P14
	void              evaluate(Scene* scene, bool viscousImplicit, Real rayleighFraction);
	// P14 of body `id` with extra damping and stiffness rates (a bridge formed since evaluate())
	Real bodyLimit(Body::id_t id, Real extraDamping, Real extraStiffness) const;
};

} // namespace yade
