#include "ViscBridgeGuard.hpp"
#include "Ip2_FrictMat_FrictMat_ViscBridgePhys.hpp"
#include "Law2_ScGeom_ViscBridgePhys_HertzViscous.hpp"
#include "ViscBridgeImplicitSolver.hpp"
#include "ViscBridgePhys.hpp"
#include "physics/ModelNames.hpp"
#include "physics/TimeStepBounds.hpp"
#include "physics/Validation.hpp"
#include <core/InteractionLoop.hpp>
#include <core/Scene.hpp>
#include <pkg/common/ElastMat.hpp>
#include <pkg/dem/NewtonIntegrator.hpp>
#include <pkg/dem/ScGeom.hpp>
#include <cmath>
#include <limits>
#include <mutex>
#include <sstream>

namespace yade {

CREATE_LOGGER(ViscBridgeGuard);

namespace {
	std::mutex  pendingMutex;
	std::string pendingError; // raised by the next guard that runs

	std::string takePendingError()
	{
		std::lock_guard<std::mutex> lock(pendingMutex);
		std::string                 msg;
		msg.swap(pendingError);
		return msg;
	}
	std::string fmt(Real v) { return viscbridge::formatValue(v); }
	Real        bodyKineticEnergy(const State& st) { return 0.5 * st.mass * st.vel.squaredNorm() + 0.5 * st.angVel.dot(st.inertia.cwiseProduct(st.angVel)); }
	std::string vec(const Vector3r& v)
	{
		std::ostringstream o;
		o.precision(4);
		o << "(" << v[0] << ", " << v[1] << ", " << v[2] << ")";
		return o.str();
	}
}

void ViscBridgeGuard::raiseAtNextStep(Scene* scene, const std::string& message)
{
	{
		std::lock_guard<std::mutex> lock(pendingMutex);
		if (pendingError.empty()) pendingError = message;
	}
	for (const auto& e : scene->engines)
		if (dynamic_cast<const ViscBridgeGuard*>(e.get())) return;
	vector<shared_ptr<Engine>> next = scene->_nextEngines.empty() ? scene->engines : scene->_nextEngines;
	next.insert(next.begin(), shared_ptr<Engine>(new ViscBridgeGuard));
	scene->_nextEngines = next;
}

void ViscBridgeGuard::validateScene()
{
	namespace vb = viscbridge;
	if (!(scene->dt > 0) || !std::isfinite(scene->dt)) vb::rejectValue("O", "dt", scene->dt, "> 0 [s]");

	const InteractionLoop*                          loop = nullptr;
	const Law2_ScGeom_ViscBridgePhys_HertzViscous* law  = nullptr;
	bool                                            ip2 = false, solverAfterLoop = false, newtonAfterSolver = false;
	const NewtonIntegrator*                         newton = nullptr;
	for (const auto& e : scene->engines) {
		if (const auto* l = dynamic_cast<const InteractionLoop*>(e.get())) {
			loop = l;
			for (const auto& f : l->lawDispatcher->functors)
				if (const auto* x = dynamic_cast<const Law2_ScGeom_ViscBridgePhys_HertzViscous*>(f.get())) law = x;
			for (const auto& f : l->physDispatcher->functors)
				if (dynamic_cast<const Ip2_FrictMat_FrictMat_ViscBridgePhys*>(f.get())) ip2 = true;
		}
		if (dynamic_cast<const ViscBridgeImplicitSolver*>(e.get()) && loop) solverAfterLoop = true;
		if (const auto* n = dynamic_cast<const NewtonIntegrator*>(e.get())) {
			newton            = n;
			newtonAfterSolver = solverAfterLoop;
		}
	}
	if (!loop) return;
	if (law && !ip2)
		throw std::invalid_argument("Law2_ScGeom_ViscBridgePhys_HertzViscous needs Ip2_FrictMat_FrictMat_ViscBridgePhys in the same InteractionLoop "
		                            "(it handles ViscBridgePhys only; another Ip2 makes interactions no law can handle).");
	if (ip2 && !law)
		throw std::invalid_argument("Ip2_FrictMat_FrictMat_ViscBridgePhys needs Law2_ScGeom_ViscBridgePhys_HertzViscous in the same InteractionLoop "
		                            "(no other law handles ViscBridgePhys).");
	if (ip2) {
		for (const auto& b : *scene->bodies) {
			if (!b || !b->shape) continue;
			if (!b->material || !dynamic_cast<const FrictMat*>(b->material.get()))
				throw std::invalid_argument("Body #" + std::to_string(b->getId()) + " has material "
				                            + (b->material ? b->material->getClassName() : std::string("None"))
				                            + "; allowed with Ip2_FrictMat_FrictMat_ViscBridgePhys: FrictMat or a subclass of it.");
		}
	}
	if (law && law->integrationIndex == static_cast<int>(viscbridge::Integration::implicitEuler)) {
		if (!solverAfterLoop || !newtonAfterSolver)
			throw std::invalid_argument("Law2_ScGeom_ViscBridgePhys_HertzViscous.integration='implicit' needs a ViscBridgeImplicitSolver engine between "
			                            "InteractionLoop and NewtonIntegrator; O.engines has none there (viscbridge.engines(integration='implicit') inserts it).");
		if (newton && newton->damping != 0)
			vb::rejectValue("NewtonIntegrator", "damping", newton->damping, "0 with implicit viscous integration");
	}
}

void ViscBridgeGuard::postLoad(ViscBridgeGuard&)
{
	namespace vb = viscbridge;
	try {
		vb::requireInRange("ViscBridgeGuard", "iterPeriod", iterPeriod, 1, false, 1e12, false);
		vb::requireInRange("ViscBridgeGuard", "energyMargin", energyMargin, 1, false, 1e300, false);
		vb::requireNonNegative("ViscBridgeGuard", "energyFloor", energyFloor, " [J]");
	} catch (const std::invalid_argument&) {
		iterPeriod   = lastValidPeriod;
		energyMargin = lastValidMargin;
		energyFloor  = lastValidFloor;
		throw;
	}
	lastValidPeriod = iterPeriod;
	lastValidMargin = energyMargin;
	lastValidFloor  = energyFloor;
}

Real ViscBridgeGuard::storedElasticEnergy() const
{
	// Runs over every interaction at each check: in parallel, and with a class-index test instead
	// of dynamic_cast (a ViscBridgePhys only exists on ScGeom-derived geometry: its Law2 needs it).
	const int  vbIndex = ViscBridgePhys::getClassIndexStatic();
	const long n       = static_cast<long>(scene->interactions->size());
	Real       e       = 0;
#pragma omp parallel for schedule(static) reduction(+ : e)
	for (long k = 0; k < n; ++k) {
		const shared_ptr<Interaction>& I = (*scene->interactions)[k];
		if (!I->isReal() || I->phys->getClassIndex() != vbIndex) continue;
		const auto& ph = static_cast<const ViscBridgePhys&>(*I->phys);
		const auto& g  = static_cast<const ScGeom&>(*I->geom);
		if (g.penetrationDepth <= 0) continue;
		e += 0.4 * ph.kno * std::pow(g.penetrationDepth, 2.5) + (ph.ks > 0 ? 0.5 * ph.shearElastic.squaredNorm() / ph.ks : 0.0);
	}
	return e;
}

void ViscBridgeGuard::takeReference()
{
	startPos.assign(scene->bodies->size(), Vector3r::Zero());
	startEnergy = storedElasticEnergy();
	for (const auto& b : *scene->bodies) {
		if (!b) continue;
		startPos[b->getId()] = b->state->pos;
		if (b->isDynamic()) startEnergy += 0.5 * b->state->mass * b->state->vel.squaredNorm() + 0.5 * b->state->angVel.dot(b->state->inertia.cwiseProduct(b->state->angVel));
	}
	boundaryWork     = 0;
	referenceIter    = scene->iter;
	referencePending = false;
}

std::string ViscBridgeGuard::diagnose(Body::id_t worst, const std::string& what)
{
	std::ostringstream msg;
	msg.precision(4);
	msg << "ViscBridgeGuard stopped the run at step " << scene->iter << " (t = " << scene->time << " s, dt = " << scene->dt << " s): " << what << ".";
	const bool implicit = viscousIntegrationIsImplicit(scene);
	bound.evaluate(scene, implicit, 0.4);
	if (worst >= 0 && Body::byId(worst, scene)) {
		const Body& b = *Body::byId(worst, scene);
		msg << " Body #" << worst << " at " << vec(b.state->pos) << ", velocity " << vec(b.state->vel) << ".";
		// its most demanding interaction: the smallest explicit limit
		Real                 tightest = std::numeric_limits<Real>::infinity();
		const Interaction*   which    = nullptr;
		const ViscBridgePhys* phys    = nullptr;
		for (const auto& kv : b.intrs) {
			const Interaction* I = kv.second.get();
			if (!I->isReal()) continue;
			const auto* ph = dynamic_cast<const ViscBridgePhys*>(I->phys.get());
			if (!ph) continue;
			const Real c     = (ph->bridge && !implicit) ? ph->viscousStepCoefficient : 0;
			const Real limit = viscbridge::networkLimit(c / ph->mEff, (ph->kn + 3.5 * ph->ks) / ph->mEff);
			if (limit < tightest) {
				tightest = limit;
				which    = I;
				phys     = ph;
			}
		}
		if (which) {
			msg << " Its most demanding interaction #" << which->getId1() << "+#" << which->getId2() << ": gap S = " << phys->separation << " m"
			    << (phys->bridge ? " with a bridge" : " without bridge") << ", C_n = " << phys->cn << " N·s/m (" << phys->viscousStepCoefficient
			    << " at S_min = " << phys->sMin << " m incl. tangential), C_T = " << phys->ct << " N·s/m, k_n = " << phys->kn
			    << " N/m, m* = " << phys->mEff << " kg. ";
			const Real tv = phys->viscousStepCoefficient > 0 ? phys->mEff / phys->viscousStepCoefficient : std::numeric_limits<Real>::infinity();
			if (!implicit && phys->bridge && scene->dt > 2 * tv)
				msg << "Violated: the explicit viscous pair limit dt < 2 m*/(C_n + w_t C_t) = " << 2 * tv << " s (physics.md P12).";
			else if (scene->dt > tightest)
				msg << "Violated: the pair limit 4m*/(C + sqrt(C² + 4m*k)) = " << tightest << " s (P13).";
			else
				msg << "Violated: the network limit P14 (several contacts on one body): " << bound.combined << " s.";
		}
	}
	msg << " A safe dt for the current contacts: " << 0.5 * bound.combined << " s (ViscBridgeTimeStepper, safety 0.5; "
	    << (implicit ? "implicit viscous forces, collision bound only)." : "or use integration='implicit' to lift the viscous limit).");
	return msg.str();
}

void ViscBridgeGuard::action()
{
	const std::string pending = takePendingError();
	if (!pending.empty()) {
		lastError = pending;
		throw std::runtime_error(pending);
	}
	const long signature = static_cast<long>(scene->bodies->size()) * 1000003L + static_cast<long>(scene->engines.size());
	if (signature != checkedSignature || scene->iter == 0) {
		validateScene();
		checkedSignature = signature;
		referencePending = true;
		return;
	}
	if (referencePending) {
		takeReference();
		return;
	}
	// Work of kinematic bodies (walls moved by the user) on the particles during the last step: the
	// forces the particles exerted on them are still in the force container (the guard runs before
	// ForceResetter), and the body gives the particles minus that power.
	// The displacement is taken from the positions (a velocity set for the next step, e.g. by a
	// PyRunner shaking a wall, is not the one the body moved with), with the force of the step it
	// moved in (still in the container: the guard runs before ForceResetter).
	scene->forces.sync();
	Real delivered = 0;
	lastPos.resize(scene->bodies->size(), Vector3r::Constant(std::numeric_limits<Real>::quiet_NaN()));
	if (kinematic.empty() || scene->iter % iterPeriod == 0) { // the bodies the user moves: refreshed with each check
		kinematic.clear();
		for (const auto& b : *scene->bodies)
			if (b && !b->isDynamic()) kinematic.push_back(b->getId());
	}
	for (Body::id_t id : kinematic) {
		const shared_ptr<Body>& b = Body::byId(id, scene);
		if (!b || b->isDynamic()) continue;
		const Vector3r   moved = b->state->pos - lastPos[id];
		lastPos[id]            = b->state->pos;
		if (moved.allFinite()) delivered -= scene->forces.getForce(id).dot(moved); // NaN: first call
		delivered -= scene->forces.getTorque(id).dot(b->state->angVel) * scene->dt;
	}
	boundaryWork += delivered;
	// with energy tracking, as "boundaryWork" beside NewtonIntegrator's gravWork (same sign: what
	// enters the system is negative), so that O.energy.total() also closes with moving walls
	if (scene->trackEnergy && delivered != 0) scene->energy->add(-delivered, "boundaryWork", boundaryWorkIx, false);
	if (scene->iter % iterPeriod != 0) return;
	++checks;
	Vector3r gravity = Vector3r::Zero();
	for (const auto& e : scene->engines)
		if (const auto* n = dynamic_cast<const NewtonIntegrator*>(e.get())) gravity = n->gravity;
	// Sums over the bodies in parallel; which body is at fault is only looked for when the check fails.
	Real       kinetic = 0, gravityWork = 0;
	bool       finite  = true;
	const long nBodies = static_cast<long>(scene->bodies->size());
	const long nStart  = static_cast<long>(startPos.size());
#pragma omp parallel for schedule(static) reduction(+ : kinetic, gravityWork) reduction(&& : finite)
	for (long k = 0; k < nBodies; ++k) {
		const shared_ptr<Body>& b = (*scene->bodies)[k];
		if (!b || !b->isDynamic()) continue;
		const State& st = *b->state;
		finite          = finite && st.pos.allFinite() && st.vel.allFinite() && st.angVel.allFinite();
		kinetic += bodyKineticEnergy(st);
		if (k < nStart) gravityWork += st.mass * gravity.dot(st.pos - startPos[k]);
	}
	Body::id_t fastest = -1, notFinite = -1;
	// the body with a NaN/inf, else the one with the most kinetic energy
	auto findCulprit = [&]() {
		Real fastestEnergy = -1;
		for (const auto& b : *scene->bodies) {
			if (!b || !b->isDynamic()) continue;
			const State& st = *b->state;
			if (!(st.pos.allFinite() && st.vel.allFinite() && st.angVel.allFinite())) {
				notFinite = b->getId();
				return;
			}
			if (bodyKineticEnergy(st) > fastestEnergy) {
				fastestEnergy = bodyKineticEnergy(st);
				fastest       = b->getId();
			}
		}
	};
	if (!finite) findCulprit();
	kineticEnergy = kinetic;
	energyIn      = startEnergy + std::max<Real>(0, gravityWork + boundaryWork);
	std::string what;
	if (notFinite >= 0) what = "body #" + std::to_string(notFinite) + " has a NaN or inf position or velocity";
	else {
		const Real mechanical = kinetic + storedElasticEnergy();
		if (!std::isfinite(mechanical) || mechanical > energyMargin * energyIn + energyFloor)
			what = "the kinetic + elastic energy " + fmt(mechanical) + " J exceeds what the scene had at step " + std::to_string(referenceIter)
			        + " plus the work of gravity and moving bodies since, " + fmt(energyIn) + " J (× " + fmt(energyMargin) + " allowed)";
	}
	if (what.empty()) return;
	if (finite) findCulprit();
	lastError = diagnose(notFinite >= 0 ? notFinite : fastest, what);
	LOG_ERROR(lastError);
	throw std::runtime_error(lastError);
}

} // namespace yade
