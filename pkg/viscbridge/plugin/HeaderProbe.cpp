#include "viscbridge/plugin/HeaderProbe.hpp"
#include <core/Omega.hpp>
#include <core/Scene.hpp>
#include <pkg/dem/FrictPhys.hpp>
#include <pkg/dem/ScGeom.hpp>

namespace yade {


boost::python::dict ViscBridgeHeaderProbe::read() const
{
	namespace py = boost::python;
	const shared_ptr<Scene>& scene = Omega::instance().getScene();
	py::dict out, sc;
	sc["dt"]   = scene->dt;
	sc["iter"] = scene->iter;
	sc["time"] = scene->time;
	out["scene"] = sc;

	py::list bodies;
	for (const shared_ptr<Body>& b : *scene->bodies) {
		if (!b) continue;
		const State& st = *b->state;
		py::dict d;
		d["id"]      = b->getId();
		d["pos"]     = st.pos;
		d["vel"]     = st.vel;
		d["angVel"]  = st.angVel;
		d["mass"]    = st.mass;
		d["inertia"] = st.inertia;
		bodies.append(d);
	}
	out["bodies"] = bodies;

	py::list intrs;
	for (const shared_ptr<Interaction>& I : *scene->interactions) {
		py::dict d;
		d["id1"]    = I->getId1();
		d["id2"]    = I->getId2();
		d["isReal"] = I->isReal();
		if (const ScGeom* g = dynamic_cast<const ScGeom*>(I->geom.get())) {
			d["normal"]           = g->normal;
			d["penetrationDepth"] = g->penetrationDepth;
			d["radius1"]          = g->radius1;
			d["radius2"]          = g->radius2;
			d["contactPoint"]     = g->contactPoint;
		}
		intrs.append(d);
	}
	out["interactions"] = intrs;

	py::list mats;
	for (const shared_ptr<Material>& m : scene->materials) {
		if (const FrictMat* f = dynamic_cast<const FrictMat*>(m.get())) {
			py::dict d;
			d["id"]            = f->id;
			d["young"]         = f->young;
			d["poisson"]       = f->poisson;
			d["density"]       = f->density;
			d["frictionAngle"] = f->frictionAngle;
			mats.append(d);
		}
	}
	out["materials"] = mats;
	return out;
}

} // namespace yade
