// FilmSource: what the law asks of the engine that keeps a scene's films (liquidModel 'film') when a
// bridge would form — the least liquid a bridge forms from (physics.md L0, L5).  An interface in
// this layer, so the law reads it without knowing the engine (engines/ViscBridgeLiquid implements it).
#pragma once
#include <lib/base/Math.hpp>

namespace yade {

class FilmSource {
public:
	virtual ~FilmSource() = default;
	// The least liquid [m³] from which a bridge forms (0: any liquid at all).
	virtual Real formationThreshold() const = 0;
};

} // namespace yade
