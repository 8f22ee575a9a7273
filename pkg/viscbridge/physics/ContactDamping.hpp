// Contact damping of the Hertz–Mindlin contact, selectable per scene (YADE's `en` behaviour).
#pragma once

namespace viscbridge {

struct NoContactDamping {
	static constexpr bool enabled = false;
	double                betan = 0, betas = 0;
};

// Constant restitution coefficient e: c = 2β√(m* k) with β from dampingRatioFromRestitution(e)
// for both directions, as YADE's Law2_ScGeom_MindlinPhys_Mindlin with `en` (and es = en).
struct RestitutionContactDamping {
	static constexpr bool enabled = true;
	double                betan, betas;
};

} // namespace viscbridge
