// Ig2_Wall_Sphere_ViscBridgeScGeom: the geometry of a sphere and a wall, also before contact, within
// `detectionDistance`, so that a liquid bridge can form at a distance (formationDistance > 0).
// YADE's own Ig2_Wall_Sphere_ScGeom creates interactions at contact only (sphere–sphere and box–sphere
// pairs have interactionDetectionFactor for this).
#pragma once
#include "viscbridge/yade/AttributeRollback.hpp"
#include <pkg/dem/Ig2_Facet_Sphere_ScGeom.hpp>

namespace yade {

class Ig2_Wall_Sphere_ViscBridgeScGeom : public Ig2_Wall_Sphere_ScGeom {
public:
	bool go(const shared_ptr<Shape>& cm1,
	        const shared_ptr<Shape>& cm2,
	        const State&             state1,
	        const State&             state2,
	        const Vector3r&          shift2,
	        const bool&              force,
	        const shared_ptr<Interaction>& c) override;
	void postLoad(Ig2_Wall_Sphere_ViscBridgeScGeom&);
	AttributeRollback<Real> rollback;
	// clang-format off
	YADE_CLASS_BASE_DOC_ATTRS_CTOR(Ig2_Wall_Sphere_ViscBridgeScGeom, Ig2_Wall_Sphere_ScGeom,
		"Same :yref:`ScGeom` as :yref:`Ig2_Wall_Sphere_ScGeom`, but a new interaction is also created "
		"when the sphere's surface is within detectionDistance of the wall, so that a liquid bridge "
		"can form before contact (:yref:`Ip2_FrictMat_FrictMat_ViscBridgePhys.formationDistance`).",
		((Real,detectionDistance,0,Attr::triggerPostLoad,"Largest surface gap at which a new interaction is created [m]; 0: at contact only, like the base class."))
		, /* ctor */ rollback.keep(std::tie(detectionDistance));
	);
	// clang-format on
	FUNCTOR2D(Wall, Sphere);
	DEFINE_FUNCTOR_ORDER_2D(Wall, Sphere);
};
REGISTER_SERIALIZABLE(Ig2_Wall_Sphere_ViscBridgeScGeom);

} // namespace yade
