#include "viscbridge/yade/Ig2_Wall_Sphere_ViscBridgeScGeom.hpp"
#include "viscbridge/core/util/Validation.hpp"
#include "viscbridge/yade/BridgeRangeGeometry.hpp"

namespace yade {

void Ig2_Wall_Sphere_ViscBridgeScGeom::postLoad(Ig2_Wall_Sphere_ViscBridgeScGeom&)
{
	rollback.check(std::tie(detectionDistance), [&] {
		viscbridge::requireNonNegative("Ig2_Wall_Sphere_ViscBridgeScGeom", "detectionDistance", detectionDistance, " [m]; 0 means at contact only");
	});
}

bool Ig2_Wall_Sphere_ViscBridgeScGeom::go(
        const shared_ptr<Shape>&       cm1,
        const shared_ptr<Shape>&       cm2,
        const State&                   state1,
        const State&                   state2,
        const Vector3r&                shift2,
        const bool&                    force,
        const shared_ptr<Interaction>& c)
{
	if (c->isReal() || detectionDistance <= 0) return Ig2_Wall_Sphere_ScGeom::go(cm1, cm2, state1, state2, shift2, force, c);
	return bridgeRange::createWithinRange<Ig2_Wall_Sphere_ScGeom>(*this, detectionDistance, cm1, cm2, state1, state2, shift2, force, c, false);
}

} // namespace yade
