// ViscBridgeState: the per-particle quantities ViscBridge's engines own, kept in the body's State so
// that they are saved with the scene, stay with the body when bodies are erased or added (ids are
// never reused by YADE), and travel with it when yade.mpy migrates bodies between ranks.
//
// A body created by YADE's utilities has a plain State; it is converted in place the first time an
// engine writes one of these quantities (ViscBridgeState::of, serial code only), as YADE converts
// states for its thermal engine.  Readers inside the interaction loop use peek(): a plain State
// reads as the defaults.  Add a quantity: one attribute below, documented with its unit and owner.
#pragma once
#include <core/Body.hpp>
#include <core/State.hpp>
#include "viscbridge/yade/AttributeRollback.hpp"

namespace yade {

class ViscBridgeState : public State {
	AttributeRollback<Real> rollback;

public:
	// Converting a State: every attribute of State copied (a State has no usable copy constructor).
	explicit ViscBridgeState(const State& source);
	// The body's ViscBridgeState, converting its State in place when it is a plain one.  Not for the
	// interaction loop (it replaces body.state); from an engine it takes the GIL for the replacement.
	static ViscBridgeState& of(Body& body);
	// The body's ViscBridgeState, or nullptr while it has a plain State (any thread).
	static const ViscBridgeState* peek(const Body& body);
	static shared_ptr<ViscBridgeState> pyOf(const shared_ptr<Body>& body); // of(), for Python
	void                          postLoad(ViscBridgeState&);
	// clang-format off
	YADE_CLASS_BASE_DOC_ATTRS_CTOR_PY(ViscBridgeState, State,
		"State of a particle with the quantities ViscBridge keeps per particle (besides :yref:`State`'s). "
		"ViscBridge converts a body's plain :yref:`State` into one when it first stores such a quantity; "
		"you can also assign one yourself (``b.state = ViscBridgeState()`` before setting mass and position, "
		"or ``ViscBridgeState.of(body)`` converts a body's state keeping all of it). Saved with the scene and moved with the body by yade.mpy.",
		((Real,film,0,Attr::triggerPostLoad,"Volume of the liquid film on the particle [m³], >= 0: the liquid it gives to new bridges and takes back from ruptured ones with :yref:`Ip2_FrictMat_FrictMat_ViscBridgePhys.liquidModel` = 'film' (physics.md §11; set it with viscbridge.liquid.set_film or add)."))
		((bool,wettable,true,,"Whether a liquid bridge can form on this body (any liquid model). False makes a dry boundary or particle: its interactions created from then on are dry contacts (viscbridge.liquid.make_dry)."))
		,
		/* ctor */ createIndex(); rollback.keep(std::tie(film));
		,
		/* py */
		.def("of", &ViscBridgeState::pyOf, (boost::python::arg("body")),
		     "The body's ViscBridgeState: its state if it is one, else its :yref:`State` converted in place (every attribute kept).")
		.staticmethod("of")
	);
	// clang-format on
	REGISTER_CLASS_INDEX(ViscBridgeState, State);
};
REGISTER_SERIALIZABLE(ViscBridgeState);

} // namespace yade
