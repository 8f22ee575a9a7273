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
	if (restoredIn != scene) restoreLiquidModel();
	const std::vector<BridgeEvent>& events = ViscBridgeContext::of(scene).events(scene->iter);
	if (distributed::active(scene)) return actOverRanks(events); // [MPI] a collective, also without events here
	masterChecked  = false;
	ownedSignature = 0;
	if (events.empty()) return;
	const auto own = distributed::ownership(scene);
	formBridges(formationsHere(events), [this](Body::id_t id) { return filmOf(id); }, own); // films as at the start of the step (L1)
	returnLiquid(events, own); // then the ruptured bridges' liquid (available from the next step)
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

ViscBridgePhys* ViscBridgeLiquid::bridgeHere(Body::id_t id1, Body::id_t id2) const
{
	const shared_ptr<Interaction>& I  = scene->interactions->find(id1, id2);
	auto*                          ph = I && I->isReal() ? dynamic_cast<ViscBridgePhys*>(I->phys.get()) : nullptr;
	return ph && ph->bridge ? ph : nullptr;
}

std::vector<ViscBridgeLiquid::Formation> ViscBridgeLiquid::formationsHere(const std::vector<BridgeEvent>& events) const
{
	std::vector<Formation> formations; // in the events' order: by (id1, id2)
	for (const BridgeEvent& e : events)
		if (e.kind == BridgeEvent::Kind::formed)
			if (const ViscBridgePhys* ph = bridgeHere(e.id1, e.id2)) formations.push_back({ e.id1, e.id2, ph->bridgeVolume });
	return formations;
}

std::vector<vb::FilmTake> ViscBridgeLiquid::settleTakes(const std::vector<Formation>& formations, const FilmOf& film, std::vector<bool>& alive) const
{
	// L1 and L5: what each new bridge would take with every body's film shared among its new bridges.
	// A bridge that would take less than the threshold and is the smallest such at both its bodies
	// does not form, and its bodies share among fewer; repeated until every bridge left takes enough.
	// The result does not depend on the visiting order, and a thinly shared film still forms its best bridges.
	std::vector<vb::FilmTake> takes(formations.size(), vb::FilmTake { 0, 0, 0 });
	alive.assign(formations.size(), true);
	auto tooSmall = [&](std::size_t i) { return alive[i] && (!(takes[i].volume > 0) || takes[i].volume < minBridgeVolume); };
	for (;;) {
		std::map<Body::id_t, int> newBridges;
		for (std::size_t i = 0; i < formations.size(); ++i)
			if (alive[i]) ++newBridges[formations[i].id1], ++newBridges[formations[i].id2];
		std::map<Body::id_t, std::size_t> smallestAt; // each body's smallest too-small bridge (first in order on ties)
		for (std::size_t i = 0; i < formations.size(); ++i) {
			if (!alive[i]) continue;
			const Formation& f = formations[i];
			takes[i] = vb::takeFromFilms(vb::filmOffer(film(f.id1), newBridges[f.id1]), vb::filmOffer(film(f.id2), newBridges[f.id2]), f.cap);
			if (!tooSmall(i)) continue;
			for (const Body::id_t id : { f.id1, f.id2 })
				if (auto [at, fresh] = smallestAt.emplace(id, i); !fresh && takes[i].volume < takes[at->second].volume) at->second = i;
		}
		if (smallestAt.empty()) return takes;
		for (std::size_t i = 0; i < formations.size(); ++i)
			if (tooSmall(i) && smallestAt[formations[i].id1] == i && smallestAt[formations[i].id2] == i) alive[i] = false;
	}
}

void ViscBridgeLiquid::formBridges(const std::vector<Formation>& formations, const FilmOf& film, const distributed::Ownership& own)
{
	std::vector<bool>               alive;
	const std::vector<vb::FilmTake> takes = settleTakes(formations, film, alive);
	auto                            ownFilm = [&](Body::id_t id) { return scene->bodies->exists(id) && own.body(*Body::byId(id, scene)); };
	for (std::size_t i = 0; i < formations.size(); ++i) {
		const Formation& f  = formations[i];
		ViscBridgePhys*  ph = bridgeHere(f.id1, f.id2); // under mpy: null for a bridge of other ranks
		if (!alive[i]) {
			if (ph) ph->bridge = false; // no liquid (first step after loading) or too little: a dry contact
			continue;
		}
		if (takes[i].from1 > 0 && ownFilm(f.id1)) addToFilm(f.id1, -takes[i].from1);
		if (takes[i].from2 > 0 && ownFilm(f.id2)) addToFilm(f.id2, -takes[i].from2);
		if (ph) giveBridgeVolume(*ph, takes[i].volume);
		if (own.pair(f.id1, f.id2, scene)) ++formed; // once over the ranks
	}
}

void ViscBridgeLiquid::returnLiquid(const std::vector<BridgeEvent>& events, const distributed::Ownership& own)
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
		// under mpy both ranks of a bridge between them see it rupture: each gives its own body its share
		if (share1 > 0 && own.body(*b1)) addToFilm(e.id1, share1 * e.volume);
		if (share1 < 1 && own.body(*b2)) addToFilm(e.id2, (1 - share1) * e.volume);
		if (own.pair(e.id1, e.id2, scene)) ++ruptured;
	}
}

} // namespace yade
