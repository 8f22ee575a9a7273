// Contact damping of the Hertz–Mindlin contact (YADE's `en` behaviour, physics.md P2b), one slot of
// SubModels.hpp.  Selected by the restitution coefficient, not by a name: e_n < 1 damps.
#pragma once
#include "viscbridge/core/models/SubModel.hpp"

namespace viscbridge {

struct NoContactDamping {
	static constexpr const char*                name         = "none";
	static constexpr Capabilities               capabilities { false, true, false, false, true };
	static constexpr std::array<EnergyKey, 0> energyKeys {};
	double                                      betan = 0, betas = 0;
	static NoContactDamping make(const BridgeInputs&) { return {}; }
	double                  stepCoefficient(const BridgeInputs&) const { return 0; }
};

// Constant restitution coefficient e: c = 2β√(m* k) with β from dampingRatioFromRestitution(e)
// for both directions, as YADE's Law2_ScGeom_MindlinPhys_Mindlin with `en` (and es = en).  Its
// dashpots follow the contact stiffness, so the time stepper takes them from the current k.
struct RestitutionContactDamping {
	static constexpr const char*                name         = "restitution";
	static constexpr Capabilities               capabilities { true, true, false, false, true };
	static constexpr std::array<EnergyKey, 1> energyKeys { EnergyKey::contactDampDissip };
	double                                      betan, betas;
	static RestitutionContactDamping make(const BridgeInputs& b) { return { b.dampingRatio, b.dampingRatio }; }
	double stepCoefficient(const BridgeInputs&) const { return 0; }
};

} // namespace viscbridge
