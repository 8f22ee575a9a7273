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
	rollback.check(std::tie(ruptureSplit), [&] {
		split = static_cast<vb::RuptureSplit>(vb::parseName("ViscBridgeLiquid", "ruptureSplit", ruptureSplit, vb::ruptureSplitNames, "split"));
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
				if (auto* ip2 = dynamic_cast<Ip2_FrictMat_FrictMat_ViscBridgePhys*>(functor.get()); ip2 && ip2->liquidModel != film) {
					ip2->liquidModel = film;
					ip2->postLoad(*ip2);
				}
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

void ViscBridgeLiquid::formBridges(const std::vector<BridgeEvent>& events)
{
	// L1: every body's number of new bridges first, so that what it offers each does not depend on order
	std::map<Body::id_t, int> newBridges;
	std::vector<ViscBridgePhys*> phys(events.size(), nullptr);
	for (std::size_t i = 0; i < events.size(); ++i) {
		const BridgeEvent& e = events[i];
		if (e.kind != BridgeEvent::Kind::formed) continue;
		const shared_ptr<Interaction>& I  = scene->interactions->find(e.id1, e.id2);
		auto*                          ph = I && I->isReal() ? dynamic_cast<ViscBridgePhys*>(I->phys.get()) : nullptr;
		if (!ph || !ph->bridge) continue;
		phys[i] = ph;
		++newBridges[e.id1], ++newBridges[e.id2];
	}
	std::map<Body::id_t, Real> offer;
	for (const auto& [id, n] : newBridges)
		offer[id] = vb::filmOffer(filmOf(id), n);
	for (std::size_t i = 0; i < events.size(); ++i) {
		if (!phys[i]) continue;
		// until now the bridge held its cap, the largest volume it may take (the Ip2's)
		const vb::FilmTake take = vb::takeFromFilms(offer[events[i].id1], offer[events[i].id2], phys[i]->bridgeVolume);
		if (!(take.volume > 0)) { // no liquid (only in the first step after loading, before the films were asked)
			phys[i]->bridge = false;
			continue;
		}
		if (take.from1 > 0) addToFilm(events[i].id1, -take.from1);
		if (take.from2 > 0) addToFilm(events[i].id2, -take.from2);
		giveBridgeVolume(*phys[i], take.volume);
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
