#include "viscbridge/engines/ViscBridgeLiquid.hpp"
#include "viscbridge/core/pair/PairGeometry.hpp"
#include "viscbridge/distributed/Distributed.hpp"
#include "viscbridge/yade/ViscBridgeContext.hpp"
#include "viscbridge/yade/ViscBridgePhys.hpp"
#include "viscbridge/yade/ViscBridgeState.hpp"
#include "viscbridge/yade/Ip2_FrictMat_FrictMat_ViscBridgePhys.hpp"
#include <core/Scene.hpp>
#include <core/InteractionLoop.hpp>
#include <pkg/common/Sphere.hpp>

namespace yade {

CREATE_LOGGER(ViscBridgeLiquid);

namespace vb = viscbridge;

void ViscBridgeLiquid::postLoad(ViscBridgeLiquid&)
{
	rollback.check(std::tie(ruptureSplit, minBridgeVolume), [&] {
		split = static_cast<vb::RuptureSplit>(vb::parseName("ViscBridgeLiquid", "ruptureSplit", ruptureSplit, vb::ruptureSplitNames, "split"));
		vb::requireNonNegative("ViscBridgeLiquid", "minBridgeVolume", minBridgeVolume, " [m³]; 0 means any liquid forms a bridge");
	});
}

void ViscBridgeLiquid::action()
{
	// [MPI] a bridge between two ranks would take from a film that only one rank owns
	if (distributed::active(scene))
		throw std::runtime_error("ViscBridgeLiquid: liquidModel='film' does not run under yade.mpy (a bridge between two subdomains would take "
		                         "liquid from a film only one of them owns); run it serially or with threads (-j), or use liquidModel='fixed'.");
	if (restoredIn != scene) restoreLiquidModel();
	const std::vector<BridgeEvent>& events = ViscBridgeContext::of(scene).events(scene->iter);
	if (events.empty()) return;
	formBridges(events);  // from the films as they were at the start of the step (L1)
	returnLiquid(events); // then the ruptured bridges' liquid (available from the next step)
}

void ViscBridgeLiquid::restoreLiquidModel()
{
	// The liquid model is not saved with the Ip2 and the physics (so that scenes saved before it
	// existed load); this engine is, and a scene that has it takes its liquid from the films.
	const std::string film = vb::liquidModelNames[static_cast<int>(vb::LiquidModel::film)];
	for (const auto& engine : scene->engines)
		if (auto* loop = dynamic_cast<InteractionLoop*>(engine.get()))
			for (const auto& functor : loop->physDispatcher->functors)
				if (auto* ip2 = dynamic_cast<Ip2_FrictMat_FrictMat_ViscBridgePhys*>(functor.get()); ip2 && ip2->liquidModel != film)
					ip2->restoreLiquidModel(film);
	for (const auto& I : *scene->interactions)
		if (auto* ph = I->isReal() ? dynamic_cast<ViscBridgePhys*>(I->phys.get()) : nullptr; ph && !ph->constants.fromFilms) {
			ph->liquidModel         = film;
			ph->constants.fromFilms = true;
		}
	restoredIn = scene;
}

Real ViscBridgeLiquid::filmOf(Body::id_t id) const
{
	const shared_ptr<Body>& b = Body::byId(id, scene);
	const ViscBridgeState*  s = b ? ViscBridgeState::peek(*b) : nullptr;
	return s ? s->film : 0;
}

void ViscBridgeLiquid::addToFilm(Body::id_t id, Real volume)
{
	Real& film = ViscBridgeState::of(*Body::byId(id, scene)).film;
	film       = std::max<Real>(0, film + volume); // a body that gives all it has ends at 0, not −ulp
}

void ViscBridgeLiquid::giveBridgeVolume(ViscBridgePhys& ph, Real volume)
{
	ph.bridgeVolume = volume;
	ph.sRup         = vb::ruptureDistance(volume, ph.contactAngle);
	ph.buildConstants(ph.selection);
}

std::vector<vb::FilmTake> ViscBridgeLiquid::settleTakes(const std::vector<BridgeEvent>& events, std::vector<ViscBridgePhys*>& phys)
{
	// L1 and L5: what each new bridge would take with every body's film shared among its new bridges.
	// A bridge that would take less than the threshold and is the smallest such at both its bodies
	// does not form, and its bodies share among fewer; repeated until every bridge left takes enough.
	// The result does not depend on the visiting order, and a thinly shared film still forms its best bridges.
	std::vector<vb::FilmTake> takes(events.size(), vb::FilmTake { 0, 0, 0 });
	auto tooSmall = [&](std::size_t i) { return phys[i] && (!(takes[i].volume > 0) || takes[i].volume < minBridgeVolume); };
	for (;;) {
		std::map<Body::id_t, int> newBridges;
		for (std::size_t i = 0; i < events.size(); ++i)
			if (phys[i]) ++newBridges[events[i].id1], ++newBridges[events[i].id2];
		std::map<Body::id_t, std::size_t> smallestAt; // each body's smallest too-small bridge (first in event order on ties)
		for (std::size_t i = 0; i < events.size(); ++i) {
			if (!phys[i]) continue;
			// until now the bridge held its cap, the largest volume it may take (the Ip2's)
			takes[i] = vb::takeFromFilms(vb::filmOffer(filmOf(events[i].id1), newBridges[events[i].id1]),
			                             vb::filmOffer(filmOf(events[i].id2), newBridges[events[i].id2]), phys[i]->bridgeVolume);
			if (!tooSmall(i)) continue;
			for (const Body::id_t id : { events[i].id1, events[i].id2 })
				if (auto [at, fresh] = smallestAt.emplace(id, i); !fresh && takes[i].volume < takes[at->second].volume) at->second = i;
		}
		if (smallestAt.empty()) return takes;
		for (std::size_t i = 0; i < events.size(); ++i)
			if (tooSmall(i) && smallestAt[events[i].id1] == i && smallestAt[events[i].id2] == i) {
				phys[i]->bridge = false; // no liquid (first step after loading) or too little: a dry contact
				phys[i]         = nullptr;
			}
	}
}

void ViscBridgeLiquid::formBridges(const std::vector<BridgeEvent>& events)
{
	std::vector<ViscBridgePhys*> phys(events.size(), nullptr);
	for (std::size_t i = 0; i < events.size(); ++i) {
		const BridgeEvent& e = events[i];
		if (e.kind != BridgeEvent::Kind::formed) continue;
		const shared_ptr<Interaction>& I  = scene->interactions->find(e.id1, e.id2);
		auto*                          ph = I && I->isReal() ? dynamic_cast<ViscBridgePhys*>(I->phys.get()) : nullptr;
		if (ph && ph->bridge) phys[i] = ph;
	}
	const std::vector<vb::FilmTake> takes = settleTakes(events, phys); // from the films as at the start of the step
	for (std::size_t i = 0; i < events.size(); ++i) {
		if (!phys[i]) continue;
		if (takes[i].from1 > 0) addToFilm(events[i].id1, -takes[i].from1);
		if (takes[i].from2 > 0) addToFilm(events[i].id2, -takes[i].from2);
		giveBridgeVolume(*phys[i], takes[i].volume);
		++formed;
	}
}

void ViscBridgeLiquid::returnLiquid(const std::vector<BridgeEvent>& events)
{
	for (const BridgeEvent& e : events) {
		if (e.kind != BridgeEvent::Kind::ruptured || !(e.volume > 0)) continue;
		const shared_ptr<Body>&b1 = Body::byId(e.id1, scene), &b2 = Body::byId(e.id2, scene);
		if (!b1 && !b2) {
			lostVolume += e.volume;
			continue;
		}
		// a side without film (a wall, a facet) or erased gets nothing: the other side takes it all
		auto radius = [](const shared_ptr<Body>& b) {
			const auto* s = b ? dynamic_cast<const Sphere*>(b->shape.get()) : nullptr;
			return s ? s->radius : Real(0);
		};
		const Real share1 = vb::ruptureShare1(split, radius(b1), radius(b2));
		if (share1 > 0) addToFilm(e.id1, share1 * e.volume);
		if (share1 < 1) addToFilm(e.id2, (1 - share1) * e.volume);
		++ruptured;
	}
}

} // namespace yade
