// Values no wet granulation run uses — almost always a unit mistake (a radius in mm typed as m, a
// film of 2 m³) — said once per scene through YADE's log; the run goes on (a warning, not an error:
// the value is legal).  Checked with the scene (ViscBridgeGuard, before the first step and after a
// change); the Ip2 says its own (viscosity, bridge volume) when they are set.  The bounds:
// core/models/Plausible.hpp.
#pragma once
#include <core/Scene.hpp>

namespace yade {

void warnImplausible(Scene* scene);

} // namespace yade
