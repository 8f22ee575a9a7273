// ViscBridgeHeaderProbe: reads a live scene through YADE's C++ headers.
//
// The plugin is compiled against YADE's source headers with feature macros derived from the
// installed binary.  If a header or a macro did not match, member offsets would differ and the
// values read here would disagree with YADE's own Python view of the same objects; the test
// tests/yade/test_header_probe.py compares the two on a scene with distinct non-default values.
#pragma once
#include <lib/serialization/Serializable.hpp>
#include <boost/python/dict.hpp>
#include <boost/python/list.hpp>

namespace yade {

class ViscBridgeHeaderProbe : public Serializable {
public:
	boost::python::dict read() const;
	std::string builtAgainst() const { return VISCBRIDGE_YADE_VERSION; }
	// clang-format off
	YADE_CLASS_BASE_DOC_ATTRS_CTOR_PY(ViscBridgeHeaderProbe, Serializable,
		"Reads the current scene through the C++ headers ViscBridge was compiled with: ``Scene`` "
		"(dt, iter, time), every ``Body``/``State`` (id, pos, vel, angVel, mass, inertia), every "
		"``Interaction`` (id1, id2, isReal) with its ``ScGeom`` (normal, penetrationDepth, radius1, "
		"radius2, contactPoint), and every ``FrictMat`` (young, poisson, density, frictionAngle). "
		"Comparing :yref:`ViscBridgeHeaderProbe.read` with YADE's Python view proves that the "
		"plugin's headers and feature macros match the running YADE binary.",
		/* no attributes */,
		/* ctor */,
		.def("read", &ViscBridgeHeaderProbe::read,
		     "Return a dict with keys 'scene', 'bodies', 'interactions', 'materials', read in C++.")
		.add_property("yadeVersion", &ViscBridgeHeaderProbe::builtAgainst,
		     "Version of the YADE headers this plugin was compiled against.")
	);
	// clang-format on
};
REGISTER_SERIALIZABLE(ViscBridgeHeaderProbe);

} // namespace yade
