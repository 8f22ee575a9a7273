// ViscBridgeLiquid: the liquid of a scene with liquidModel 'film' (physics.md §11).  After the
// interaction loop it reads the step's bridge events (ViscBridgeContext) and moves liquid between
// the particles' films (ViscBridgeState.film) and the bridges (ViscBridgePhys.bridgeVolume): a new
// bridge takes its volume from the films (L1, L2), a ruptured one gives it back (L3).  Between the
// two, the total liquid does not change.
#pragma once
#include "viscbridge/core/liquid/FilmExchange.hpp"
#include "viscbridge/distributed/Distributed.hpp"
#include "viscbridge/yade/AttributeRollback.hpp"
#include "viscbridge/yade/BridgeEvent.hpp"
#include "viscbridge/yade/FilmSource.hpp"
#include <core/GlobalEngine.hpp>
#include <functional>
#include <map>
#include <vector>

namespace yade {

class ViscBridgePhys;

class ViscBridgeLiquid : public GlobalEngine, public FilmSource {
	AttributeRollback<std::string, Real> rollback;
	viscbridge::RuptureSplit       split = viscbridge::RuptureSplit::half;
	const Scene*                   restoredIn = nullptr; // the scene whose liquid model this engine has set

	void restoreLiquidModel(); // after loading: the Ip2s and the bridges are 'film' again (not saved)

	// A bridge that formed in the step: its bodies and the largest volume it may take (the Ip2's cap).
	struct Formation {
		Body::id_t id1, id2;
		Real       cap;
	};
	using FilmOf = std::function<Real(Body::id_t)>;
	std::vector<Formation> formationsHere(const std::vector<BridgeEvent>& events) const;
	void formBridges(const std::vector<Formation>& formations, const FilmOf& film, const distributed::Ownership& own);
	// the volume each new bridge takes (L1, L2, L5); `alive` false for those that cannot form
	std::vector<viscbridge::FilmTake> settleTakes(const std::vector<Formation>& formations, const FilmOf& film, std::vector<bool>& alive) const;
	void returnLiquid(const std::vector<BridgeEvent>& events, const distributed::Ownership& own);
	void giveBridgeVolume(ViscBridgePhys& ph, Real volume); // and the constants that follow from it (L4)
	ViscBridgePhys* bridgeHere(Body::id_t id1, Body::id_t id2) const; // the new bridge's physics, if this rank holds it
	Real filmOf(Body::id_t id) const;                                  // 0 for a body without film or gone
	void addToFilm(Body::id_t id, Real volume);

	// [MPI] ViscBridgeLiquidOverRanks.cpp (physics.md L8): every rank settles the whole scene's
	// formations of the step from their owners' films, and changes the films of its own bodies.
	void actOverRanks(const std::vector<BridgeEvent>& events);
	std::vector<Formation> formationsOverRanks(const std::vector<BridgeEvent>& events, std::map<Body::id_t, Real>& films, bool& anyRupture, bool& moved);
	void refreshMirrorFilms(); // the mirrors' films from their owners, for the law's next step
	void refuseFilmsOfTheMaster(); // a master's body whose film would change: the workers cannot update it
	bool   masterChecked  = false; // refuseFilmsOfTheMaster done for this split
	size_t ownedSignature = 0;     // distributed::ownedBodiesSignature at the last step under mpy

public:
	void action() override;
	void postLoad(ViscBridgeLiquid&);
	Real formationThreshold() const override { return minBridgeVolume; }
	// clang-format off
	YADE_CLASS_BASE_DOC_ATTRS_CTOR(ViscBridgeLiquid, GlobalEngine,
		"Conserves the liquid of the bridges with :yref:`Ip2_FrictMat_FrictMat_ViscBridgePhys.liquidModel` = 'film' "
		"(physics.md §11). Put it right after the InteractionLoop (:yref:`viscbridge.engines()` does). Each step it reads the bridges that "
		"formed and ruptured in the interaction loop (:yref:`ViscBridgeContext`, in an order independent of the number of threads): "
		"a new bridge takes its volume from the films of its two particles (:yref:`ViscBridgeState.film`) — each particle gives "
		"$F/n$ to each of its $n$ bridges formed in the step, the bridge takes at most bridgeVolume/bridgeVolumeRel of the Ip2 and "
		"the excess stays in the films (L1, L2, after YADE's LiqControl); no bridge forms from less than minBridgeVolume (L5) — and its viscous, capillary and rupture constants follow "
		"its volume (L4); a ruptured bridge gives its volume back to the films (L3). Walls and facets carry no film. "
		"In the step a bridge forms, its forces use the largest volume it may take (its volume is known once the step's "
		"formations are counted). The liquid of a bridge whose bodies are both erased is counted in lostVolume. "
		"Under yade.mpy every rank settles the whole scene's formations of a step from their owners' films, changes only its own "
		"particles' films and then refreshes its copies of its neighbours' films (physics.md L8, docs/cluster.md).",
		((string,ruptureSplit,viscbridge::ruptureSplitNames[0],Attr::triggerPostLoad,"How a ruptured bridge's volume returns to the films (L3): 'half' (half to each particle; all of it to the particle of a wall bridge) or 'radius' (in proportion to the particles' surfaces, $r_i^2/(r_1^2+r_2^2)$)."))
		((Real,minBridgeVolume,0,Attr::triggerPostLoad,"The least liquid a bridge forms from [m³] (L5): where the two films hold less (or, among bridges formed in the same step, offer less), the contact stays dry and the films keep their liquid. 0: any liquid forms a bridge. With a threshold the binder does not spread over the whole bed in ever thinner bridges (MercuryDPM's liquidBridgeVolumeMin, YADE's LiqControl Vmin; calibrated on drums by Pourandi et al. 2026). Allowed: a finite number ≥ 0 (above the Ip2's bridge volume no bridge forms)."))
		((long,formed,0,Attr::readonly,"Bridges that took liquid from the films since the engine was created (under yade.mpy: those this rank accounts for; the sum over the ranks is the scene's)."))
		((long,ruptured,0,Attr::readonly,"Ruptured bridges whose liquid returned to the films (under yade.mpy: as formed)."))
		((Real,lostVolume,0,Attr::readonly,"Liquid of ruptured bridges whose particles were both erased [m³] (gone from the scene)."))
		,
		/* ctor */ rollback.keep(std::tie(ruptureSplit, minBridgeVolume));
	);
	// clang-format on
	DECLARE_LOGGER;
};
REGISTER_SERIALIZABLE(ViscBridgeLiquid);

} // namespace yade
