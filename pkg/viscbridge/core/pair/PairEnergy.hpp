// The energy of one interaction's step [J] (physics.md §6), by O.energy key (models/EnergyKeys.hpp):
// dissipation and stored energy when tracking; the work of conservative forces (capillary) always
// (ViscBridgeGuard counts it), with the sign of a dissipation (−work done, P21).  Each model writes
// the keys it declares in its `energyKeys`; the law books exactly those.
#pragma once
#include "viscbridge/core/models/EnergyKeys.hpp"
#include <array>

namespace viscbridge {

struct PairEnergy {
	std::array<double, energyKeyCount> value {};
	double&                            operator[](EnergyKey k) { return value[static_cast<std::size_t>(k)]; }
	double                             operator[](EnergyKey k) const { return value[static_cast<std::size_t>(k)]; }
};

} // namespace viscbridge
