// The scene's wet contacts (real interactions with a ViscBridgePhys) sorted by their bodies' ids.
// YADE's interaction container holds them in the order the collider inserted them, which depends on
// the number of threads; a per-body sum taken in that order differs in its last bits between runs,
// and a bed with dry contacts grows such a difference into another trajectory.  Every sum over
// contacts that reaches the motion (the time step, the implicit system, the error estimate) runs in
// this order (docs/architecture.md, "Bit-identical on any number of threads").
#pragma once
#include "viscbridge/yade/ViscBridgeContext.hpp"
#include "viscbridge/yade/ViscBridgePhys.hpp"
#include <core/Scene.hpp>
#include <algorithm>

namespace yade {

// The contacts for which keep(interaction, physics) holds, ordered by (smaller id, larger id).  The
// test runs on all threads; `out` is reused (no allocation once it has grown).
template <class Keep> void orderedWetContacts(Scene* scene, Keep keep, OrderedContacts& out)
{
	// After the loop of a step whose law kept every contact's forces (ViscBridgeForceSum): that list,
	// already in this order, instead of a scan of every interaction
	ViscBridgeContext& context = ViscBridgeContext::of(scene);
	if (context.keptEveryContact(scene->iter)) {
		out.clear();
		for (const ContactForce* f : context.forces(scene->iter, scene->bodies->size())) {
			Interaction& I = *f->interaction;
			if (I.isReal() && keep(I, static_cast<const ViscBridgePhys&>(*I.phys)))
				out.push_back({ contactOrderKey(f->id1, f->id2), &I });
		}
		return;
	}
	InteractionContainer& all   = *scene->interactions;
	const long            n     = static_cast<long>(all.size());
	const int             index = ViscBridgePhys::getClassIndexStatic();
	out.assign(n, { 0, nullptr });
#pragma omp parallel for schedule(static)
	for (long k = 0; k < n; ++k) {
		Interaction& I = *all[k];
		if (!I.isReal() || I.phys->getClassIndex() != index || !keep(I, static_cast<const ViscBridgePhys&>(*I.phys))) continue;
		out[k] = { contactOrderKey(I.getId1(), I.getId2()), &I };
	}
	out.erase(std::remove_if(out.begin(), out.end(), [](const auto& e) { return !e.second; }), out.end());
	std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
}

} // namespace yade
