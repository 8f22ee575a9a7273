// Every O.energy key a wet contact books (physics.md §6), in one table.  A model declares the keys
// it books (its `energyKeys`, of this enum); the law and the implicit solver book a model's energy
// under exactly those keys, with the name and reset flag of this table.
#pragma once
#include <array>
#include <cstddef>

namespace viscbridge {

enum class EnergyKey : std::size_t {
	viscDissipNormal,
	viscDissipTangential,
	viscDissipRotational,
	contactDampDissip,
	plastDissip,
	elastPotential,
	capillaryWork,
	count
};
inline constexpr std::size_t energyKeyCount = static_cast<std::size_t>(EnergyKey::count);

struct EnergyKeySpec {
	const char* name;  // the O.energy key
	bool        reset; // a potential energy, cleared every step (YADE's reset=true), else cumulative
};

inline constexpr std::array<EnergyKeySpec, energyKeyCount> energyKeySpecs { {
        { "viscDissipNormal", false },
        { "viscDissipTangential", false },
        { "viscDissipRotational", false },
        { "contactDampDissip", false },
        { "plastDissip", false },
        { "elastPotential", true },
        { "capillaryWork", false },
} };

constexpr const EnergyKeySpec& spec(EnergyKey k) { return energyKeySpecs[static_cast<std::size_t>(k)]; }

} // namespace viscbridge
