// ViscBridgeLiquid under yade.mpy (physics.md L8).  A bridge between bodies of two ranks is
// computed on both, and each rank owns only its own bodies' films; so every rank gathers the step's
// formations of the whole scene with their bodies' films from the owners, settles them all with the
// serial rules (L1, L2, L5: the same list in the same order, so the same arithmetic on every rank),
// and changes only the films of its own bodies.  A rupture is seen by the ranks of both bodies, each
// giving its own body its share (L3).  Then the mirrors' films are refreshed from their owners, for
// the law's decision whether a bridge can form (L0) in the next step.
#include "viscbridge/distributed/Distributed.hpp"
#include "viscbridge/engines/ViscBridgeLiquid.hpp"
#include "viscbridge/yade/ViscBridgeState.hpp"
#include <core/Scene.hpp>
#include <pkg/common/Sphere.hpp>
#include <algorithm>
#include <sstream>

namespace yade {

void ViscBridgeLiquid::actOverRanks(const std::vector<BridgeEvent>& events)
{
	if (!masterChecked) distributed::collectively(scene, [&] { refuseFilmsOfTheMaster(); });
	masterChecked = true;
	std::map<Body::id_t, Real>   films;
	bool                         anyRupture = false, moved = false;
	const std::vector<Formation> formations = formationsOverRanks(events, films, anyRupture, moved);
	if (moved) // on every rank at once: the same gathered flags
		throw std::runtime_error("ViscBridgeLiquid: yade.mpy moved bodies between ranks (mp.REALLOCATE_FREQUENCY > 0, or migrateBodies) "
		                         "in a scene whose bridges take their liquid from the films: a moved body's bridges are created anew "
		                         "on its new rank, which would take their liquid from the films a second time. Keep "
		                         "mp.REALLOCATE_FREQUENCY = 0 (mpy's default) with liquidModel='film'.");
	const auto                   own        = distributed::ownership(scene);
	auto film = [&films](Body::id_t id) { // a body no rank gave: a master's, whose film is 0 (refuseFilmsOfTheMaster)
		const auto at = films.find(id);
		return at == films.end() ? Real(0) : at->second;
	};
	formBridges(formations, film, own);
	returnLiquid(events, own);
	if (!formations.empty() || anyRupture) refreshMirrorFilms(); // the same decision on every rank
}

std::vector<ViscBridgeLiquid::Formation>
ViscBridgeLiquid::formationsOverRanks(const std::vector<BridgeEvent>& events, std::map<Body::id_t, Real>& films, bool& anyRupture, bool& moved)
{
	// This rank's part: [formations, (id1, id2, cap)..., films, (id, film)..., ruptures, moved], the films
	// of its own bodies among the formations' (ids travel as doubles: exact below 2^53).
	const auto                   own  = distributed::ownership(scene);
	const std::vector<Formation> here = formationsHere(events);
	std::vector<double>          mine { double(here.size()) };
	std::vector<Body::id_t>      givers;
	for (const Formation& f : here) {
		mine.insert(mine.end(), { double(f.id1), double(f.id2), double(f.cap) });
		for (const Body::id_t id : { f.id1, f.id2 })
			if (own.body(*Body::byId(id, scene))) givers.push_back(id);
	}
	std::sort(givers.begin(), givers.end());
	givers.erase(std::unique(givers.begin(), givers.end()), givers.end());
	mine.push_back(double(givers.size()));
	for (const Body::id_t id : givers)
		mine.insert(mine.end(), { double(id), double(filmOf(id)) });
	mine.push_back(double(std::count_if(events.begin(), events.end(), [](const BridgeEvent& e) {
		return e.kind == BridgeEvent::Kind::ruptured && e.volume > 0;
	})));
	const size_t owned = distributed::ownedBodiesSignature(scene); // changed: mpy moved bodies between ranks
	mine.push_back(double(ownedSignature != 0 && owned != ownedSignature));
	ownedSignature = owned;

	const std::vector<double> all = distributed::allGatherJoined(scene, mine);
	std::vector<Formation>    formations;
	for (size_t at = 0; at < all.size();) { // rank after rank
		const auto nFormed = static_cast<size_t>(all[at++]);
		for (size_t k = 0; k < nFormed; ++k, at += 3)
			formations.push_back({ static_cast<Body::id_t>(all[at]), static_cast<Body::id_t>(all[at + 1]), all[at + 2] });
		const auto nFilms = static_cast<size_t>(all[at++]);
		for (size_t k = 0; k < nFilms; ++k, at += 2)
			films[static_cast<Body::id_t>(all[at])] = all[at + 1];
		const bool ruptures = all[at++] > 0, changed = all[at++] > 0; // both read, whatever came before
		anyRupture          = anyRupture || ruptures;
		moved               = moved || changed;
	}
	// a bridge between two ranks came from both, equal: once, in the serial events' order (by ids)
	std::sort(formations.begin(), formations.end(), [](const Formation& a, const Formation& b) {
		return std::tie(a.id1, a.id2) < std::tie(b.id1, b.id2);
	});
	formations.erase(
	        std::unique(formations.begin(), formations.end(), [](const Formation& a, const Formation& b) { return a.id1 == b.id1 && a.id2 == b.id2; }),
	        formations.end());
	return formations;
}

void ViscBridgeLiquid::refreshMirrorFilms()
{
	const distributed::Halo          halo = distributed::halo(scene);
	std::vector<std::vector<double>> send, received;
	for (size_t j = 0; j < halo.ranks.size(); ++j) {
		send.emplace_back();
		for (const Body::id_t id : halo.sent[j])
			send.back().push_back(filmOf(id));
		received.emplace_back(halo.received[j].size(), 0.0);
	}
	distributed::exchange(scene, halo, send, received);
	for (size_t j = 0; j < halo.ranks.size(); ++j)
		for (size_t k = 0; k < halo.received[j].size(); ++k) {
			const Body::id_t id = halo.received[j][k];
			if (!scene->bodies->exists(id)) continue;
			Body& b = *Body::byId(id, scene);
			if (received[j][k] > 0 || ViscBridgeState::peek(b)) ViscBridgeState::of(b).film = received[j][k];
		}
}

void ViscBridgeLiquid::refuseFilmsOfTheMaster()
{
	// The master owns walls, facets and fixed bodies but computes no interaction: a film of its own
	// would change only on the workers, each its own way.  Walls and facets carry no film (L0); a
	// sphere the master keeps must be dry.
	if (distributed::rank(scene) != 0) return;
	const auto own = distributed::ownership(scene);
	for (const auto& b : *scene->bodies) {
		if (!b || !own.body(*b) || distributed::isSubdomainBody(*b)) continue;
		const ViscBridgeState* s      = ViscBridgeState::peek(*b);
		const bool             sphere = dynamic_cast<const Sphere*>(b->shape.get()) != nullptr;
		if ((s && s->film > 0) || (sphere && (!s || s->wettable))) {
			std::ostringstream msg;
			msg << "ViscBridgeLiquid: under yade.mpy, body #" << b->id << " (a " << (sphere ? "sphere" : "boundary")
			    << " the master keeps: fixed, or left to subdomain 0) " << (s && s->film > 0 ? "carries a film" : "is wettable")
			    << "; the master computes no interaction, so its film could not take part in the workers' bridges. "
			    << "Make it dry (viscbridge.liquid.make_dry(ids=[" << b->id << "]) and set_film(" << b->id
			    << ", 0)) or give it to a worker, or run the scene serially or with threads (-j).";
			throw std::invalid_argument(msg.str());
		}
	}
}

} // namespace yade
