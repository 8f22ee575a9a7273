// A liquid bridge formed or ruptured: what Law2_ScGeom_ViscBridgePhys_HertzViscous publishes into
// the scene's ViscBridgeContext, for any engine that acts on the bridges' life (the time stepper's
// corrections, liquid bookkeeping, agglomerate tracking).  The interaction itself may be gone when
// an event is read (a ruptured bridge's interaction is erased in the same step): everything a
// consumer needs of the bridge is in the event.
#pragma once
#include <core/Body.hpp>
#include <tuple>

namespace yade {

struct BridgeEvent {
	enum class Kind : int { formed = 0, ruptured = 1 };
	Kind       kind;
	Body::id_t id1, id2;   // the interaction's bodies (id1 < id2 as YADE orders them)
	Real       volume;     // the bridge's liquid volume [m³]
	Real       separation; // the surface gap S when it happened [m]
	Real       dampingRate, stiffnessRate; // the bridge's rates in P14 when published (ViscBridgePhys::stepDampingRate, stepStiffnessRate): a ruptured one's last

	// The order in which a step's events are read (independent of the thread that published them).
	friend bool operator<(const BridgeEvent& a, const BridgeEvent& b)
	{
		return std::make_tuple(a.id1, a.id2, static_cast<int>(a.kind)) < std::make_tuple(b.id1, b.id2, static_cast<int>(b.kind));
	}
};

} // namespace yade
