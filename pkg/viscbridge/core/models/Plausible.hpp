// The values wet granulation runs use, beyond which a value is legal but almost surely a unit
// mistake (a radius in mm typed as m, a viscosity in mPa·s typed as Pa·s): ViscBridge says so once
// in YADE's log and runs on (scene/Plausibility, the Ip2, the Python tools through _registry.PLAUSIBLE).
#pragma once

namespace viscbridge::plausible {

inline constexpr double maxRadius    = 0.1;  // m: granules of a few cm at most
inline constexpr double minViscosity = 1e-4; // Pa·s: thinner than water (1e-3)
inline constexpr double maxViscosity = 1e3;  // Pa·s: detergent pastes, the most viscous binders

} // namespace viscbridge::plausible
