// Liquid that is conserved (physics.md §11, L1–L4): how a bridge takes its volume from the films of
// its two particles when it forms, and how it gives it back when it ruptures.  YADE-free: the liquid
// engine (engines/ViscBridgeLiquid) applies these rules to the bridge events of a step.
#pragma once
#include "viscbridge/core/util/Validation.hpp"
#include <algorithm>
#include <array>

namespace viscbridge {

// How a ruptured bridge's volume goes back to the films (L3).
enum class RuptureSplit : int { half = 0, radius = 1 };
inline constexpr std::array<const char*, 2> ruptureSplitNames { "half", "radius" };

// What a liquid model is (selected on the Ip2, L0): a fixed volume from nowhere, or the particles' films.
enum class LiquidModel : int { fixed = 0, film = 1 };
inline constexpr std::array<const char*, 2> liquidModelNames { "fixed", "film" };

// L1 (after YADE's LiqControl, Mani et al. 2013): a particle with film F and n bridges formed in
// the same step offers F/n to each, so the result does not depend on the order the bridges are
// visited in.  A side without a film (a wall, a facet) offers 0.
inline double filmOffer(double film, int newBridges) { return newBridges > 0 ? film / newBridges : 0.0; }

// L2: the bridge takes both offers, at most `cap`; capped, each side gives in proportion to its
// offer and the rest stays in its film.
struct FilmTake {
	double volume, from1, from2;
};
inline FilmTake takeFromFilms(double offer1, double offer2, double cap)
{
	const double offered = offer1 + offer2;
	if (!(offered > 0)) return { 0, 0, 0 };
	const double volume = std::min(offered, cap), scale = volume / offered;
	return { volume, offer1 * scale, offer2 * scale };
}

// L3: the share of a ruptured bridge's volume that goes to side 1 (side 2 gets the rest).  A side
// without a film (radius 0: a wall, a facet) gets nothing; 'radius' splits in proportion to the
// particles' surfaces, r1²/(r1²+r2²).
inline double ruptureShare1(RuptureSplit split, double radius1, double radius2)
{
	if (!(radius2 > 0)) return 1.0;
	if (!(radius1 > 0)) return 0.0;
	if (split == RuptureSplit::half) return 0.5;
	return radius1 * radius1 / (radius1 * radius1 + radius2 * radius2);
}

} // namespace viscbridge
