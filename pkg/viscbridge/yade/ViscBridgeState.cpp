#include "viscbridge/yade/ViscBridgeState.hpp"
#include "viscbridge/core/util/Validation.hpp"
#include <lib/pyutil/gil.hpp>

namespace yade {

ViscBridgeState::ViscBridgeState(const State& source)
        : ViscBridgeState()
{
	se3            = source.se3; // pos and ori are references into se3
	vel            = source.vel;
	mass           = source.mass;
	angVel         = source.angVel;
	angMom         = source.angMom;
	inertia        = source.inertia;
	refPos         = source.refPos;
	refOri         = source.refOri;
	blockedDOFs    = source.blockedDOFs;
	isDamped       = source.isDamped;
	densityScaling = source.densityScaling;
}

ViscBridgeState& ViscBridgeState::of(Body& body)
{
	if (auto* s = dynamic_cast<ViscBridgeState*>(body.state.get())) return *s;
	auto converted = shared_ptr<ViscBridgeState>(new ViscBridgeState(*body.state));
	{
		// The old State may be owned by a Python object (utils.sphere made it): dropping it then
		// releases a Python reference, which needs the GIL also in the simulation's thread.
		gilLock lock;
		body.state = converted;
	}
	return *converted;
}

shared_ptr<ViscBridgeState> ViscBridgeState::pyOf(const shared_ptr<Body>& body)
{
	if (!body) throw std::invalid_argument("ViscBridgeState.of: body=None; allowed: a body of O.bodies.");
	of(*body);
	return YADE_PTR_DYN_CAST<ViscBridgeState>(body->state);
}

const ViscBridgeState* ViscBridgeState::peek(const Body& body) { return dynamic_cast<const ViscBridgeState*>(body.state.get()); }

void ViscBridgeState::postLoad(ViscBridgeState&)
{
	rollback.check(std::tie(film), [&] { viscbridge::requireNonNegative("ViscBridgeState", "film", film, " [m³]"); });
}

} // namespace yade
