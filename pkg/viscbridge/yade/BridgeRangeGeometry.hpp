// What the two range-extending geometry functors share: a new interaction within `range` of contact.
#pragma once
#include <core/Interaction.hpp>
#include <pkg/common/Sphere.hpp>
#include <pkg/dem/ScGeom.hpp>

namespace yade {
namespace bridgeRange {

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

} // namespace bridgeRange
} // namespace yade
