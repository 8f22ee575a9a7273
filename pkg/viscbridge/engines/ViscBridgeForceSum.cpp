#include "viscbridge/engines/ViscBridgeForceSum.hpp"
#include "viscbridge/yade/ViscBridgeContext.hpp"
#include <core/Scene.hpp>

namespace yade {

CREATE_LOGGER(ViscBridgeForceSum);

void ViscBridgeForceSum::action()
{
	// Placed elsewhere the law would not hand it the forces (they would be lost): say where it belongs.
	if (!ViscBridgeContext::hasEngineAfterLoop(scene, getClassName()))
		throw std::runtime_error("ViscBridgeForceSum: it must run after InteractionLoop and before NewtonIntegrator "
		                         "(O.engines = viscbridge.engines(...) puts it right after the InteractionLoop).");
	const size_t n = scene->bodies->size();
	force.assign(n, Vector3r::Zero());
	torque.assign(n, Vector3r::Zero());
	touched.assign(n, 0);
	// In the contacts' order (by their bodies' ids), whatever the threads: a body's sum is the same
	// sequence of additions in every run.  It is added once: one term per body in YADE's force slots
	// (with the implicit solver's, two: a sum that cannot depend on the order).
	for (const ContactForce* f : ViscBridgeContext::of(scene).forces(scene->iter, n)) {
		force[f->id1] += f->force1, torque[f->id1] += f->torque1, touched[f->id1] = 1;
		force[f->id2] -= f->force1, torque[f->id2] += f->torque2, touched[f->id2] = 1;
	}
	const long nBodies = static_cast<long>(n);
#pragma omp parallel for schedule(static)
	for (long id = 0; id < nBodies; ++id)
		if (touched[id]) {
			scene->forces.addForce(static_cast<Body::id_t>(id), force[id]);
			scene->forces.addTorque(static_cast<Body::id_t>(id), torque[id]);
		}
}

} // namespace yade
