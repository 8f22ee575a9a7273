#include "viscbridge/engines/ViscBridgeForceSum.hpp"
#include "viscbridge/yade/ViscBridgeContext.hpp"
#include "viscbridge/yade/ViscBridgePhys.hpp"
#include <core/Scene.hpp>

namespace yade {

CREATE_LOGGER(ViscBridgeForceSum);

void ViscBridgeForceSum::action()
{
	// Placed elsewhere the law would not hand it the forces (they would be lost): say where it belongs.
	if (!ViscBridgeContext::hasEngineAfterLoop(scene, getClassName()))
		throw std::runtime_error("ViscBridgeForceSum: it must run after InteractionLoop and before NewtonIntegrator "
		                         "(O.engines = viscbridge.engines(...) puts it right after the InteractionLoop).");
	const long  nBodies   = static_cast<long>(scene->bodies->size());
	const long  iter      = scene->iter;
	const auto& physIndex = ViscBridgePhys::getClassIndexStatic();
	// Each body sums its own contacts, in its map's order of partner ids, and adds the sum once: one
	// term per body in YADE's force slots (with the implicit solver's, two: a sum that cannot depend on the order).
#pragma omp parallel for schedule(static)
	for (long i = 0; i < nBodies; ++i) {
		const shared_ptr<Body>& b = (*scene->bodies)[i];
		if (!b) continue;
		Vector3r force = Vector3r::Zero(), torque = Vector3r::Zero();
		bool     any   = false;
		for (const auto& [other, I] : b->intrs) {
			if (!I->phys || I->phys->getClassIndex() != physIndex) continue;
			const auto& ph = static_cast<const ViscBridgePhys&>(*I->phys);
			if (ph.sumIter != iter) continue;
			const bool first = I->getId1() == b->id;
			force += first ? ph.sumForce1 : Vector3r(-ph.sumForce1);
			torque += first ? ph.sumTorque1 : ph.sumTorque2;
			any = true;
		}
		if (!any) continue;
		scene->forces.addForce(b->id, force);
		scene->forces.addTorque(b->id, torque);
	}
}

} // namespace yade
