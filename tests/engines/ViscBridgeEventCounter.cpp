// A test engine that consumes the law's bridge events the way any new engine would: it includes the
// scene's context and the physics class, and nothing of the other engines (docs/architecture.md,
// "A new engine").  Built into libviscbridge_test_engines.so (tests/engines/), loaded only by the tests.
#include "viscbridge/yade/ViscBridgeContext.hpp"
#include "viscbridge/yade/ViscBridgePhys.hpp"
#include <core/GlobalEngine.hpp>
#include <core/Scene.hpp>
#include <boost/functional/hash.hpp>
#include <algorithm>
#include <cstdio>

namespace yade {

class ViscBridgeEventCounter : public GlobalEngine {
	size_t hash = 0;

public:
	void action() override
	{
		const std::vector<BridgeEvent>& events = ViscBridgeContext::of(scene).events(scene->iter);
		if (!std::is_sorted(events.begin(), events.end())) ++outOfOrder;
		for (const BridgeEvent& e : events) {
			const bool formation = e.kind == BridgeEvent::Kind::formed;
			(formation ? formed : ruptured) += 1;
			(formation ? volumeFormed : volumeRuptured) += e.volume;
			// what the event says must be what the interaction shows after the loop
			const shared_ptr<Interaction>& I  = scene->interactions->find(e.id1, e.id2);
			const auto*                    ph = I && I->isReal() ? dynamic_cast<const ViscBridgePhys*>(I->phys.get()) : nullptr;
			if ((ph && ph->bridge) != formation) ++mismatches;
			boost::hash_combine(hash, scene->iter);
			boost::hash_combine(hash, static_cast<int>(e.kind));
			boost::hash_combine(hash, e.id1);
			boost::hash_combine(hash, e.id2);
		}
		char text[20];
		std::snprintf(text, sizeof text, "%016zx", hash);
		digest = text;
	}
	// clang-format off
	YADE_CLASS_BASE_DOC_ATTRS(ViscBridgeEventCounter, GlobalEngine,
		"Test engine (tests only): counts the bridge events of :yref:`ViscBridgeContext` after the interaction loop and "
		"checks each against the interaction it names.",
		((long,formed,0,Attr::readonly,"Formation events seen."))
		((long,ruptured,0,Attr::readonly,"Rupture events seen."))
		((Real,volumeFormed,0,Attr::readonly,"Sum of the volumes of the bridges formed [m³]."))
		((Real,volumeRuptured,0,Attr::readonly,"Sum of the volumes of the bridges ruptured [m³]."))
		((long,mismatches,0,Attr::readonly,"Events that disagree with the interaction's bridge state after the loop."))
		((long,outOfOrder,0,Attr::readonly,"Steps whose events did not come in (id1, id2, kind) order."))
		((string,digest,"",Attr::readonly,"Hash of every event seen (step, kind, bodies), in order: equal runs give equal digests."))
	);
	// clang-format on
};
REGISTER_SERIALIZABLE(ViscBridgeEventCounter);

YADE_PLUGIN((ViscBridgeEventCounter));

} // namespace yade
