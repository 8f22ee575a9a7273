#include "viscbridge/scene/NetworkOfScene.hpp"
#include "viscbridge/yade/OrderedWetContacts.hpp"
#include "viscbridge/yade/ViscBridgePhys.hpp"
#include "viscbridge/core/timestep/PairMaps.hpp"
#include <pkg/dem/ScGeom.hpp>

namespace yade {

namespace {
	// 1/√m and 1/√I per degree of freedom, 0 for a blocked one (it does not move under forces)
	viscbridge::Vec6 scaleOf(const State& st)
	{
		viscbridge::Vec6 s;
		for (int d = 0; d < 6; ++d) {
			const Real inertia = d < 3 ? st.mass : st.inertia[d - 3];
			s[d]               = (st.blockedDOFs & State::axisDOF(d % 3, d >= 3)) || !(inertia > 0) ? 0.0 : 1 / std::sqrt(inertia);
		}
		return s;
	}
}

void NetworkOfScene::gather(Scene* scene, bool viscousExplicit)
{
	namespace vb = viscbridge;
	compactOf.assign(scene->bodies->size(), -1);
	idOf.clear();
	op.scale.clear();
	op.pairs.clear();
	op.key.clear();
	for (const auto& b : *scene->bodies) {
		if (!b || !b->isDynamic() || !(b->state->mass > 0)) continue;
		compactOf[b->getId()] = static_cast<int>(idOf.size());
		idOf.push_back(b->getId());
		op.key.push_back(b->getId()); // the start vector's noise follows the body, not the numbering
		op.scale.push_back(scaleOf(*b->state));
	}
	// in the order of the bodies' ids (OrderedWetContacts): the same limit on any number of threads
	orderedWetContacts(scene, [](const Interaction&, const ViscBridgePhys&) { return true; }, contacts);
	for (const auto& [key, I] : contacts) {
		const auto& ph = static_cast<const ViscBridgePhys&>(*I->phys);
		const int   i1 = compactOf[I->getId1()], i2 = compactOf[I->getId2()];
		if (i1 < 0 && i2 < 0) continue;
		const vb::PairNow now { static_cast<const ScGeom&>(*I->geom).normal, ph.separation, ph.radius1, ph.radius2, ph.kn, ph.ks, ph.bridge };
		const vb::PairMaps m = vb::pairMaps(ph.constants, ph.selection, now, viscousExplicit);
		if (m.damping.valid || m.stiffness.valid) op.pairs.push_back({ i1, i2, m.damping, m.stiffness });
	}
}

void NetworkOfScene::modeFromIds(const std::vector<viscbridge::Vec6>& byId, viscbridge::VecX& mode) const
{
	mode.setZero(op.size());
	for (std::size_t i = 0; i < idOf.size(); ++i)
		if (static_cast<std::size_t>(idOf[i]) < byId.size()) mode.segment<6>(6 * i) = byId[idOf[i]];
}

void NetworkOfScene::modeToIds(const viscbridge::VecX& mode, std::vector<viscbridge::Vec6>& byId) const
{
	byId.assign(compactOf.size(), viscbridge::Vec6::Zero());
	for (std::size_t i = 0; i < idOf.size(); ++i)
		byId[idOf[i]] = mode.segment<6>(6 * i);
}

} // namespace yade
