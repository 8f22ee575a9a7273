#include "ViscBridgePhys.hpp"
#include "physics/ModelNames.hpp"

namespace yade {

std::string ViscBridgePhys::normalModelName() const { return viscbridge::normalModelNames.at(normalModel); }
std::string ViscBridgePhys::tangentialModelName() const { return viscbridge::tangentialModelNames.at(tangentialModel); }

} // namespace yade
