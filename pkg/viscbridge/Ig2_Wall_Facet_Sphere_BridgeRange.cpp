#include "Ig2_Wall_Facet_Sphere_BridgeRange.hpp"
#include <pkg/common/Sphere.hpp>
#include <pkg/dem/ScGeom.hpp>
#include "physics/Validation.hpp"

namespace yade {

namespace {
	// A new interaction within `range` of contact: let YADE's functor compute the geometry for a
	// sphere enlarged by `range` (it then sees an overlap), and take the enlargement back out of the
	// result.  Everything radius-dependent in both functors (penetration depth, the contact point of
	// a facet, the reference radii) is linear in the sphere radius, so this reproduces exactly the
	// geometry the functor itself computes for the same pair once the interaction exists.
	template <class Base>
	bool createWithinRange(
	        Base&                          functor,
	        Real                           range,
	        const shared_ptr<Shape>&       cm1,
	        const shared_ptr<Shape>&       cm2,
	        const State&                   state1,
	        const State&                   state2,
	        const Vector3r&                shift2,
	        const bool&                    force,
	        const shared_ptr<Interaction>& c,
	        bool                           contactPointDependsOnRadius)
	{
		const Real radius   = static_cast<const Sphere*>(cm2.get())->radius;
		auto       enlarged = shared_ptr<Sphere>(new Sphere(radius + range));
		if (!functor.Base::go(cm1, enlarged, state1, state2, shift2, force, c)) return false;
		auto* g = static_cast<ScGeom*>(c->geom.get());
		g->penetrationDepth -= range;
		if (contactPointDependsOnRadius) g->contactPoint += 0.5 * range * g->normal;
		g->radius1 *= radius / (radius + range);
		g->radius2 = radius;
		return true;
	}

	// detectionDistance >= 0; a rejected value leaves the previous one in place
	template <class F> void validateDistance(F& f, const char* name)
	{
		try {
			viscbridge::requireNonNegative(name, "detectionDistance", f.detectionDistance, " [m]; 0 means at contact only");
		} catch (const std::invalid_argument&) {
			f.detectionDistance = f.lastValidDistance;
			throw;
		}
		f.lastValidDistance = f.detectionDistance;
	}
}

void Ig2_Wall_Sphere_ViscBridgeScGeom::postLoad(Ig2_Wall_Sphere_ViscBridgeScGeom&) { validateDistance(*this, "Ig2_Wall_Sphere_ViscBridgeScGeom"); }
void Ig2_Facet_Sphere_ViscBridgeScGeom::postLoad(Ig2_Facet_Sphere_ViscBridgeScGeom&) { validateDistance(*this, "Ig2_Facet_Sphere_ViscBridgeScGeom"); }

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
	return createWithinRange<Ig2_Wall_Sphere_ScGeom>(*this, detectionDistance, cm1, cm2, state1, state2, shift2, force, c, false);
}

bool Ig2_Facet_Sphere_ViscBridgeScGeom::go(
        const shared_ptr<Shape>&       cm1,
        const shared_ptr<Shape>&       cm2,
        const State&                   state1,
        const State&                   state2,
        const Vector3r&                shift2,
        const bool&                    force,
        const shared_ptr<Interaction>& c)
{
	if (c->isReal() || detectionDistance <= 0) return Ig2_Facet_Sphere_ScGeom::go(cm1, cm2, state1, state2, shift2, force, c);
	return createWithinRange<Ig2_Facet_Sphere_ScGeom>(*this, detectionDistance, cm1, cm2, state1, state2, shift2, force, c, true);
}

} // namespace yade
