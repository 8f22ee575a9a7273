#include "viscbridge/scene/Plausibility.hpp"
#include "viscbridge/core/linalg/Types.hpp"
#include "viscbridge/core/models/Plausible.hpp"
#include "viscbridge/core/util/Validation.hpp"
#include "viscbridge/yade/ViscBridgeContext.hpp"
#include "viscbridge/yade/ViscBridgeState.hpp"
#include <pkg/common/Sphere.hpp>
#include <cmath>

namespace yade {

void warnImplausible(Scene* scene)
{
	namespace vb = viscbridge;
	ViscBridgeContext& context = ViscBridgeContext::of(scene);
	for (const auto& b : *scene->bodies) {
		const auto* sphere = b ? dynamic_cast<const Sphere*>(b->shape.get()) : nullptr;
		if (!sphere) continue;
		const std::string body = "Body #" + std::to_string(b->getId());
		if (sphere->radius > vb::plausible::maxRadius)
			context.warnOnce("radius", body + ": Sphere.radius=" + vb::formatValue(sphere->radius) + " m is above " + vb::formatValue(vb::plausible::maxRadius)
			                                   + " m, larger than the particles of any wet granulation run (µm to cm): are the lengths in m?");
		const ViscBridgeState* s      = ViscBridgeState::peek(*b);
		const Real             volume = 4.0 / 3.0 * vb::pi * std::pow(sphere->radius, 3);
		if (s && s->film > volume)
			context.warnOnce("film", body + ": ViscBridgeState.film=" + vb::formatValue(s->film) + " m³ is more than the sphere's own volume ("
			                                 + vb::formatValue(volume) + " m³): films are in m³ (for a fraction of the volume multiply by it).");
	}
}

} // namespace yade
