#include "viscbridge/scene/SceneValidation.hpp"
#include "viscbridge/distributed/Distributed.hpp"
#include "viscbridge/yade/Ip2_FrictMat_FrictMat_ViscBridgePhys.hpp"
#include "viscbridge/yade/Law2_ScGeom_ViscBridgePhys_HertzViscous.hpp"
#include "viscbridge/yade/SchemeChooser.hpp"
#include "viscbridge/core/models/Registry.hpp"
#include "viscbridge/core/util/Validation.hpp"
#include <core/Clump.hpp>
#include <core/InteractionLoop.hpp>
#include <pkg/common/Box.hpp>
#include <pkg/common/ElastMat.hpp>
#include <pkg/common/Facet.hpp>
#include <pkg/common/KinematicEngines.hpp>
#include <pkg/common/Sphere.hpp>
#include <pkg/common/Wall.hpp>
#include <pkg/dem/NewtonIntegrator.hpp>
#include <boost/functional/hash.hpp>
#include <cmath>

namespace yade {

namespace {
	namespace vb = viscbridge;

	std::string bodyName(const Body& b) { return "Body #" + std::to_string(b.getId()); }

	// The shapes ViscBridge's geometry functors pair with spheres: only these meet the Ip2, so only
	// these need a FrictMat (a clump, or an MPI subdomain of yade.mpy, has none).
	bool meetsTheLaw(const Shape* s)
	{
		return dynamic_cast<const Sphere*>(s) || dynamic_cast<const Wall*>(s) || dynamic_cast<const Facet*>(s) || dynamic_cast<const Box*>(s);
	}

	// A Wall is an infinite axis-aligned plane: it cannot tilt, so turning it about an axis that is not
	// its normal moves nothing but the velocity YADE gives its contacts (ω × r, growing with the
	// distance from the axis), which the bridges' viscous forces turn into energy.  About its normal
	// it is a turntable, which is fine.
	void refuseTiltingWall(const Body& b, const Vector3r& axis, const std::string& by)
	{
		const auto* wall = dynamic_cast<const Wall*>(b.shape.get());
		if (!wall || !(axis.cross(Vector3r::Unit(wall->axis)).norm() > 1e-9 * axis.norm())) return;
		throw std::invalid_argument(bodyName(b) + " is a Wall (an infinite plane that cannot tilt) turned by " + by
		                            + " about an axis other than its normal: its contacts would slide at ω × r without the plane moving; "
		                              "turn facets instead (geom.facetBox, geom.facetCylinder), or turn the wall about its normal only.");
	}

	void validateBody(const Body& b)
	{
		if (const auto* s = dynamic_cast<const Sphere*>(b.shape.get()))
			if (!(s->radius > 0) || !std::isfinite(s->radius))
				throw std::invalid_argument(bodyName(b) + ": Sphere.radius=" + vb::formatValue(s->radius)
				                            + " is out of range; allowed: > 0 (finite) [m].");
		if (b.isDynamic() && !b.isClumpMember()) {
			const State& st = *b.state;
			if (!(st.mass > 0) || !std::isfinite(st.mass))
				throw std::invalid_argument(bodyName(b) + ": State.mass=" + vb::formatValue(st.mass)
				                            + " is out of range for a dynamic body; allowed: > 0 (finite) [kg] (check the radius and the material's density).");
			if (!(st.inertia.minCoeff() > 0) || !st.inertia.allFinite())
				throw std::invalid_argument(bodyName(b) + ": State.inertia has a component " + vb::formatValue(st.inertia.minCoeff())
				                            + "; allowed: > 0 (finite) [kg·m²] for a dynamic body.");
		}
		if (b.state->angVel.norm() > 0) refuseTiltingWall(b, b.state->angVel, "its angular velocity State.angVel");
		if (meetsTheLaw(b.shape.get()) && !(b.material && dynamic_cast<const FrictMat*>(b.material.get())))
			throw std::invalid_argument(bodyName(b) + " has material " + (b.material ? b.material->getClassName() : std::string("None"))
			                            + "; allowed with Ip2_FrictMat_FrictMat_ViscBridgePhys: FrictMat or a subclass of it.");
	}

	void validateTurningWalls(const Scene* scene)
	{
		const long n = static_cast<long>(scene->bodies->size());
		for (const auto& e : scene->engines)
			if (const auto* turn = dynamic_cast<const RotationEngine*>(e.get()))
				for (const Body::id_t id : turn->ids)
					if (const shared_ptr<Body> b = id >= 0 && id < n ? (*scene->bodies)[id] : shared_ptr<Body>())
						refuseTiltingWall(*b, turn->rotationAxis, turn->getClassName() + (turn->label.empty() ? std::string() : " '" + turn->label + "'"));
	}

	void validateImplicit(const Scene* scene, const ViscBridgeFunctors& f, bool solverAfterLoop, bool newtonAfterSolver, const NewtonIntegrator* newton)
	{
		// what asks for the implicit scheme: the law, or a time stepper that may switch to it
		const std::string asking = viscousIntegrationIsImplicit(scene)
		        ? "Law2_ScGeom_ViscBridgePhys_HertzViscous.integration='implicit'"
		        : "ViscBridgeTimeStepper.autoIntegration=True (it may switch to the implicit scheme)";
		if (!solverAfterLoop || !newtonAfterSolver)
			throw std::invalid_argument(asking + " needs a ViscBridgeImplicitSolver engine between InteractionLoop and NewtonIntegrator; O.engines "
			                            "has none there (viscbridge.engines(integration='implicit' or 'auto') inserts it).");
		if (newton && newton->damping != 0) vb::rejectValue("NewtonIntegrator", "damping", newton->damping, "0 with implicit viscous integration (" + asking + ")");
		// checked once here from the models' capabilities, not per bridge per step
		if (f.ip2 && !vb::TangentialModels::capabilities[f.ip2->selection.tangential].implicitCapable) {
			std::string allowed;
			for (std::size_t i = 0; i < vb::TangentialModels::size; ++i)
				if (vb::TangentialModels::capabilities[i].implicitCapable) allowed += std::string(allowed.empty() ? "'" : ", '") + vb::TangentialModels::names[i] + "'";
			throw std::invalid_argument("Ip2_FrictMat_FrictMat_ViscBridgePhys.tangentialModel='" + f.ip2->tangentialModel
			                            + "' is not dissipative (physics.md P7) and cannot be integrated implicitly; allowed with " + asking + ": "
			                            + allowed + ".");
		}
	}
}

ViscBridgeFunctors findViscBridgeFunctors(const Scene* scene)
{
	ViscBridgeFunctors out;
	for (const auto& e : scene->engines) {
		const auto* loop = dynamic_cast<const InteractionLoop*>(e.get());
		if (!loop) continue;
		out.hasLoop = true;
		for (const auto& f : loop->lawDispatcher->functors)
			if (const auto* x = dynamic_cast<const Law2_ScGeom_ViscBridgePhys_HertzViscous*>(f.get())) out.law = x;
		for (const auto& f : loop->physDispatcher->functors)
			if (const auto* x = dynamic_cast<const Ip2_FrictMat_FrictMat_ViscBridgePhys*>(f.get())) out.ip2 = x;
	}
	return out;
}

size_t sceneSignature(const Scene* scene)
{
	size_t h = 0;
	boost::hash_combine(h, scene->bodies->size());
	boost::hash_combine(h, scene->materials.size());
	for (const auto& e : scene->engines) {
		boost::hash_combine(h, static_cast<const void*>(e.get()));
		const auto* loop = dynamic_cast<const InteractionLoop*>(e.get());
		if (!loop) continue;
		// the functors, and the models and scheme they were set to (a model changed between runs
		// may be one the implicit scheme refuses)
		for (const auto& f : loop->physDispatcher->functors) {
			boost::hash_combine(h, static_cast<const void*>(f.get()));
			if (const auto* ip2 = dynamic_cast<const Ip2_FrictMat_FrictMat_ViscBridgePhys*>(f.get()))
				boost::hash_combine(h, viscbridge::comboIndex(ip2->selection));
		}
		for (const auto& f : loop->lawDispatcher->functors) {
			boost::hash_combine(h, static_cast<const void*>(f.get()));
			if (const auto* law = dynamic_cast<const Law2_ScGeom_ViscBridgePhys_HertzViscous*>(f.get())) boost::hash_combine(h, law->integrationIndex);
		}
	}
	return h;
}

void validateScene(const Scene* scene, bool checkDt)
{
	if (checkDt && (!(scene->dt > 0) || !std::isfinite(scene->dt))) vb::rejectValue("O", "dt", scene->dt, "> 0 [s]");
	const ViscBridgeFunctors f = findViscBridgeFunctors(scene);
	if (!f.hasLoop) return;
	if (f.law && !f.ip2)
		throw std::invalid_argument("Law2_ScGeom_ViscBridgePhys_HertzViscous needs Ip2_FrictMat_FrictMat_ViscBridgePhys in the same InteractionLoop "
		                            "(it handles ViscBridgePhys only; another Ip2 makes interactions no law can handle).");
	if (f.ip2 && !f.law)
		throw std::invalid_argument("Ip2_FrictMat_FrictMat_ViscBridgePhys needs Law2_ScGeom_ViscBridgePhys_HertzViscous in the same InteractionLoop "
		                            "(no other law handles ViscBridgePhys).");
	if (!f.ip2) return;
	for (const auto& b : *scene->bodies)
		if (b && b->shape && !distributed::isSubdomainBody(*b)) validateBody(*b); // [MPI] mpy's subdomains are not particles
	validateTurningWalls(scene);
	distributed::requireParticlesOnWorkers(scene);     // [MPI]
	distributed::refuseClumps(scene);                  // [MPI]
	distributed::refuseMovingBoundaries(scene);        // [MPI]
	distributed::requireOneSubdomainWhenSerial(scene); // [MPI] e.g. a merged scene run on serially
	if (!viscousIntegrationMayBeImplicit(scene)) return;
	bool                    seenLoop = false, solverAfterLoop = false, newtonAfterSolver = false;
	const NewtonIntegrator* newton = nullptr;
	for (const auto& e : scene->engines) {
		seenLoop = seenLoop || dynamic_cast<const InteractionLoop*>(e.get());
		if (e->getClassName() == "ViscBridgeImplicitSolver" && seenLoop) solverAfterLoop = true;
		if (const auto* n = dynamic_cast<const NewtonIntegrator*>(e.get())) {
			newton            = n;
			newtonAfterSolver = solverAfterLoop;
		}
	}
	validateImplicit(scene, f, solverAfterLoop, newtonAfterSolver, newton);
}

bool viscousIntegrationIsImplicit(const Scene* scene)
{
	const ViscBridgeFunctors f = findViscBridgeFunctors(scene);
	return f.law && integrationInUse(scene, f.law->integrationIndex) == viscbridge::Integration::implicitEuler;
}

bool viscousIntegrationMayBeImplicit(const Scene* scene)
{
	const auto* chooser = ViscBridgeContext::findEngine<SchemeChooser>(scene);
	return viscousIntegrationIsImplicit(scene) || (chooser && chooser->choosesIntegration());
}

} // namespace yade
