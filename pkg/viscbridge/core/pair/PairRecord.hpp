// THE per-contact record: the state and outputs one interaction carries from step to step, listed
// once.  The list is a Boost.Preprocessor sequence of YADE attribute tuples
// (type, name, default, flags, documentation), which
//   - ViscBridgePhys declares as its YADE attributes (saved with scenes, readable in Python, its
//     help() text; the order is the saved format: append, never reorder);
//   - PairRecord below declares as plain members (for the kernel tests and any use without YADE);
//   - viscbridge_registry writes into py/viscbridge/_registry.py (RECORD: the outputs VTK and the
//     Python tools list).
// Flags: Attr::readonly marks an output (a user reads it), Attr::hidden internal state (the work
// record of the last step, physics.md E1).  ViscBridgePhys inherits kn, ks, normalForce and
// shearForce from YADE's FrictPhys; PairRecord adds them, and the implicit solver's ViscousBlock.
#pragma once
#include "viscbridge/core/linalg/Types.hpp"
#include "viscbridge/core/linalg/ViscousBlock.hpp"
#include <boost/preprocessor/seq/for_each.hpp>
#include <boost/preprocessor/tuple/elem.hpp>

// clang-format off
#define VISCBRIDGE_PAIR_RECORD_ATTRS \
	/* what every step reads and writes, first (it shares cache lines with the constants) */ \
	((Vector3r,shearElastic,Vector3r::Zero(),Attr::readonly,"Elastic tangential contact force, incrementally updated (YADE sense: sustained by body 2) [N].")) \
	((Real,shearPotential,0,Attr::readonly,"Elastic energy stored in the tangential contact spring, accumulated as $\\sum(|F_s|^2-|F_{s,prev}|^2)/(2k_s)$ while energy is tracked [J].")) \
	((bool,bridge,false,Attr::readonly,"Whether the liquid bridge exists.")) \
	((Real,separation,0,Attr::readonly,"Surface gap $S$ of the last step, negative in overlap [m].")) \
	((Real,cn,0,Attr::readonly,"Normal viscous coefficient $C^n$ of the last step (0 without bridge) [N·s/m].")) \
	((Real,ct,0,Attr::readonly,"Tangential viscous coefficient $C_T$ of the last step (0 without bridge) [N·s/m].")) \
	((Real,cr,0,Attr::readonly,"Rotational coupling coefficient $C_R$ of the last step (washino, goldman) [N·s/m].")) \
	((Vector3r,normalContactForce,Vector3r::Zero(),Attr::readonly,"Hertz normal contact force on body 1 (including contact damping) [N].")) \
	((Vector3r,shearContactForce,Vector3r::Zero(),Attr::readonly,"Mindlin tangential contact force on body 1 [N].")) \
	((Vector3r,normalViscousForce,Vector3r::Zero(),Attr::readonly,"Normal viscous bridge force on body 1 (P3) [N].")) \
	((Vector3r,shearViscousForce,Vector3r::Zero(),Attr::readonly,"Tangential viscous bridge force on body 1 [N].")) \
	((Vector3r,capillaryForce,Vector3r::Zero(),Attr::readonly,"Capillary force on body 1, towards body 2 (P19, P20) [N].")) \
	/* the last step's forces, whose work is accounted at the next step (physics.md E1) */ \
	((bool,workPending,false,Attr::hidden,"A previous step's work is still to be accounted.")) \
	((Real,workCn,0,Attr::hidden,"C^n of that step.")) \
	((Real,workVn,0,Attr::hidden,"Relative normal velocity of that step.")) \
	((Vector3r,workU,Vector3r::Zero(),Attr::hidden,"Tangential relative velocity u of that step.")) \
	((Vector3r,workS,Vector3r::Zero(),Attr::hidden,"Rotational term s of that step.")) \
	((Vector2r,workM1,Vector2r::Zero(),Attr::hidden,"Resistance row (m11, m12) of that step.")) \
	((Vector2r,workM2,Vector2r::Zero(),Attr::hidden,"Resistance row (m21, m22) of that step.")) \
	((Real,workCapillary,0,Attr::hidden,"Capillary pull of that step."))
// clang-format on

#define VISCBRIDGE_RECORD_MEMBER(r, data, attr) BOOST_PP_TUPLE_ELEM(5, 0, attr) BOOST_PP_TUPLE_ELEM(5, 1, attr) = BOOST_PP_TUPLE_ELEM(5, 2, attr);

namespace viscbridge {

// A plain record, for the kernel tests and any use without YADE.
struct PairRecord {
	using Real     = double;
	using Vector3r = Vec3;
	using Vector2r = Vec2;
	BOOST_PP_SEQ_FOR_EACH(VISCBRIDGE_RECORD_MEMBER, ~, VISCBRIDGE_PAIR_RECORD_ATTRS)
	// what ViscBridgePhys inherits from YADE's FrictPhys (YADE's meaning: force sustained by body 2)
	double kn = 0, ks = 0;
	Vec3   normalForce = Vec3::Zero(), shearForce = Vec3::Zero();
	// with implicit integration, the bridge's damping for the solver (rebuilt every step, not saved)
	ViscousBlock implicitBlock;
};

} // namespace viscbridge
