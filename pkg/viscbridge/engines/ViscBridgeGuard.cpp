#include "viscbridge/engines/ViscBridgeGuard.hpp"
#include "viscbridge/yade/Ip2_FrictMat_FrictMat_ViscBridgePhys.hpp"
#include "viscbridge/yade/Law2_ScGeom_ViscBridgePhys_HertzViscous.hpp"
#include "viscbridge/yade/ViscBridgePhys.hpp"
#include "viscbridge/core/models/Registry.hpp"
#include "viscbridge/core/timestep/TimeStepBounds.hpp"
#include "viscbridge/core/util/Validation.hpp"
#include "viscbridge/scene/RunEnd.hpp"
#include "viscbridge/scene/Plausibility.hpp"
#include "viscbridge/scene/SceneValidation.hpp"
#include "viscbridge/yade/ViscBridgeContext.hpp"
#include "viscbridge/distributed/Distributed.hpp"
#include <core/InteractionLoop.hpp>
#include <core/Scene.hpp>
#include <pkg/common/ElastMat.hpp>
#include <pkg/dem/ScGeom.hpp>
#include <cmath>
#include <limits>
#include <mutex>
#include <sstream>

namespace yade {

CREATE_LOGGER(ViscBridgeGuard);

namespace {
	std::string fmt(Real v) { return viscbridge::formatValue(v); }
	// the inertia is given in the body's principal frame (clumps)
	Real rotationalKineticEnergy(const State& st)
	{
		const Vector3r w = st.ori.conjugate() * st.angVel;
		return 0.5 * w.dot(st.inertia.cwiseProduct(w));
	}
	Real bodyKineticEnergy(const State& st) { return 0.5 * st.mass * st.vel.squaredNorm() + rotationalKineticEnergy(st); }
	// 1 along the blocked translational (or rotational) axes of a body, 0 along the free ones
	Vector3r blockedAxes(const State& st, bool rotational)
	{
		return Vector3r(st.blockedDOFs & State::axisDOF(0, rotational) ? 1 : 0, st.blockedDOFs & State::axisDOF(1, rotational) ? 1 : 0,
		                st.blockedDOFs & State::axisDOF(2, rotational) ? 1 : 0);
	}
	// the bodies whose motion the energy sums follow: dynamic ones, with a clump for its members
	bool counted(const Body& b) { return b.isDynamic() && !b.isClumpMember(); }
	// The kinetic energy at the time of the positions (E5), bracketed by the two half-step velocities
	// around them: v_{n−1/2} (recovered from the last step's force, still in the container: the guard
	// runs before ForceResetter) and v_{n+1/2}.  The check takes the smaller, the reference the larger
	// (`upper`), so that the half-step offset — up to F·v·Δt/2 in a stiff contact at the collision
	// step — never makes a state look as if it had gained energy, wherever in a bounce the reference
	// was taken; the time-centred product v_{n−1/2}·v_{n+1/2} would be exact for a linear contact but
	// goes negative in the sign-flipping blow-up of an explicit viscous step, which the guard must see.
	// Rotation, clumps and blocked degrees of freedom keep the plain form.
	Real kineticEnergyAtPositions(const Body& b, Scene& scene, const Vector3r& gravity, bool upper)
	{
		const State& st = *b.state;
		if (b.isClump() || !(st.mass > 0)) return bodyKineticEnergy(st);
		// a blocked axis keeps its velocity: no acceleration along it
		const Vector3r acceleration = (scene.forces.getForce(b.getId()) / st.mass + gravity).cwiseProduct(Vector3r::Ones() - blockedAxes(st, false));
		const Vector3r before       = st.vel - acceleration * scene.dt;
		const Real     v2           = upper ? std::max(st.vel.squaredNorm(), before.squaredNorm()) : std::min(st.vel.squaredNorm(), before.squaredNorm());
		return 0.5 * st.mass * v2 + rotationalKineticEnergy(st);
	}
	using Clock = std::chrono::steady_clock;
	std::string vec(const Vector3r& v)
	{
		std::ostringstream o;
		o.precision(4);
		o << "(" << v[0] << ", " << v[1] << ", " << v[2] << ")";
		return o.str();
	}
}

void ViscBridgeGuard::postLoad(ViscBridgeGuard&)
{
	namespace vb = viscbridge;
	rollback.check(checked(), [&] {
		vb::requireInRange("ViscBridgeGuard", "iterPeriod", iterPeriod, 1, false, 1e12, false);
		vb::requireInRange("ViscBridgeGuard", "energyMargin", energyMargin, 1, false, 1e300, false);
		vb::requireNonNegative("ViscBridgeGuard", "energyFloor", energyFloor, " [J]");
	});
}

ViscBridgeGuard::InteractionEnergy ViscBridgeGuard::interactionEnergy() const
{
	// Runs over every interaction at each check: in parallel, and with a class-index test instead
	// of dynamic_cast (a ViscBridgePhys only exists on ScGeom-derived geometry: its Law2 needs it).
	const int  vbIndex = ViscBridgePhys::getClassIndexStatic();
	const long n       = static_cast<long>(scene->interactions->size());
	const auto own     = distributed::ownership(scene); // [MPI] this rank's share
	Real       elastic = 0, pending = 0;
#pragma omp parallel for schedule(static) reduction(+ : elastic, pending)
	for (long k = 0; k < n; ++k) {
		const shared_ptr<Interaction>& I = (*scene->interactions)[k];
		if (!I->isReal() || I->phys->getClassIndex() != vbIndex || !own.interaction(*I, scene)) continue;
		const auto& ph = static_cast<const ViscBridgePhys&>(*I->phys);
		const auto& g  = static_cast<const ScGeom&>(*I->geom);
		// the capillary work of the last step is booked at the next one (E1, P21): counted here with
		// the velocity it was recorded with, as Law2's capillaryInput() does
		if (ph.workPending) pending += ph.workCapillary * ph.workVn * scene->dt;
		if (g.penetrationDepth <= 0) continue;
		elastic += 0.4 * ph.kno * std::pow(g.penetrationDepth, 2.5) + (ph.ks > 0 ? 0.5 * ph.shearElastic.squaredNorm() / ph.ks : 0.0);
	}
	return { elastic, ViscBridgeContext::of(scene).conservativeWork.get() - pending };
}


Vector3r ViscBridgeGuard::gravity() const { return ViscBridgeContext::newtonGravity(scene); }

Real ViscBridgeGuard::mechanicalEnergyNow(bool upper) const
{
	const auto     own = distributed::ownership(scene); // [MPI] this rank's share, then the sum over ranks
	const Vector3r g   = gravity();
	scene->forces.sync(); // the last step's forces, for the kinetic energy at the positions' time
	Real e = interactionEnergy().elastic;
	for (const auto& b : *scene->bodies)
		if (b && counted(*b) && own.body(*b)) e += kineticEnergyAtPositions(*b, *scene, g, upper);
	return distributed::sum(scene, e);
}

void ViscBridgeGuard::takeReference(Real slack)
{
	ruptured.clear();
	startPos.assign(scene->bodies->size(), Vector3r::Zero());
	for (const auto& b : *scene->bodies)
		if (b) startPos[b->getId()] = b->state->pos;
	lastPos             = startPos; // the walls' work of the very next step counts
	startEnergy         = mechanicalEnergyNow(/*upper*/ true) + slack;
	peakEnergyIn        = startEnergy;
	capillaryAtReference = interactionEnergy().capillary;
	lastSlack           = slack;
	boundaryWork        = 0;
	referenceIter       = scene->iter;
	referencePending    = false;
	rebaselineRequested = false;
}

bool ViscBridgeGuard::startsNewRun()
{
	// A new O.run() (or a paused run resumed) shows as: a step counter that jumped, a new stopAtIter
	// or stopAtTime, the last step of a run seen the previous time, or a pause long against the steps.
	const auto now     = Clock::now();
	const bool first   = lastCallIter < 0;
	const Real gap     = first ? 0 : std::chrono::duration<Real>(now - lastCallEnd).count();
	const bool newRun  = !first
	        && (scene->iter != lastCallIter + 1 || lastStepOfRun || scene->stopAtIter != lastStopAtIter || scene->stopAtTime != lastStopAtTime
	            || (gap > 0.5 && gap > 20 * stepSeconds));
	if (!first && !newRun) stepSeconds = stepSeconds > 0 ? 0.9 * stepSeconds + 0.1 * gap : gap;
	lastCallIter   = scene->iter;
	lastStopAtIter = scene->stopAtIter;
	lastStopAtTime = scene->stopAtTime;
	lastStepOfRun  = isLastStepOfRun(*scene);
	return newRun;
}

void ViscBridgeGuard::accumulateBoundaryWork(bool newRun)
{
	// Work of kinematic bodies (walls moved by the user) on the particles during the last step (E4):
	// the forces the particles exerted on them are still in the force container (the guard runs
	// before ForceResetter), and the body gives the particles minus that power. The displacement is
	// taken from the positions (a PyRunner may move a wall by setting its position, and a velocity
	// set for the next step is not the one the body moved with); across a new run only the part its
	// velocity explains, since a wall placed by hand between runs does no work.
	scene->forces.sync();
	Real delivered = 0;
	lastPos.resize(scene->bodies->size(), Vector3r::Constant(std::numeric_limits<Real>::quiet_NaN()));
	if (kinematic.empty() || scene->iter % iterPeriod == 0) { // the bodies the user moves: refreshed with each check
		kinematic.clear();
		const auto own = distributed::ownership(scene); // [MPI] on the rank that owns them
		for (const auto& b : *scene->bodies)
			if (b && b->state->blockedDOFs != State::DOF_NONE && !b->isClumpMember() && own.body(*b)) kinematic.push_back(b->getId());
	}
	for (Body::id_t id : kinematic) {
		const shared_ptr<Body>& b = Body::byId(id, scene);
		if (!b || b->state->blockedDOFs == State::DOF_NONE) continue;
		const Vector3r moved = newRun ? Vector3r(b->state->vel * scene->dt) : Vector3r(b->state->pos - lastPos[id]);
		lastPos[id]          = b->state->pos;
		// a blocked degree of freedom moves as prescribed whatever the force on it: along it the
		// constraint does the work (all six for a wall; the blocked ones of a partly blocked sphere)
		const Vector3r force  = scene->forces.getForce(id).cwiseProduct(blockedAxes(*b->state, false));
		const Vector3r torque = scene->forces.getTorque(id).cwiseProduct(blockedAxes(*b->state, true));
		if (moved.allFinite()) delivered -= force.dot(moved); // NaN: first call
		delivered -= torque.dot(b->state->angVel) * scene->dt;
	}
	boundaryWork += delivered;
	// with energy tracking, as "boundaryWork" beside NewtonIntegrator's gravWork (same sign: what
	// enters the system is negative), so that O.energy.total() also closes with moving walls
	if (scene->trackEnergy && delivered != 0) scene->energy->add(-delivered, "boundaryWork", boundaryWorkIx, false);
}

void ViscBridgeGuard::checkEnergy()
{
	++checks;
	const Vector3r g = gravity();
	scene->forces.sync();
	// Sums over the bodies in parallel; which body is at fault is only looked for when the check fails.
	Real       kinetic = 0, gravityWork = 0;
	bool       finite  = true;
	const long nBodies = static_cast<long>(scene->bodies->size());
	const long nStart  = static_cast<long>(startPos.size());
	const auto own     = distributed::ownership(scene); // [MPI] this rank's share
#pragma omp parallel for schedule(static) reduction(+ : kinetic, gravityWork) reduction(&& : finite)
	for (long k = 0; k < nBodies; ++k) {
		const shared_ptr<Body>& b = (*scene->bodies)[k];
		if (!b || !counted(*b) || !own.body(*b)) continue;
		const State& st = *b->state;
		finite          = finite && st.pos.allFinite() && st.vel.allFinite() && st.angVel.allFinite();
		kinetic += kineticEnergyAtPositions(*b, *scene, g, /*upper*/ false);
		if (k < nStart) gravityWork += st.mass * g.dot(st.pos - startPos[k]);
	}
	// a wall or other body whose motion is prescribed, gone NaN, takes no part in the sums (its work
	// is skipped as at a first call, the collider drops its contacts): spheres would pass through it
	Body::id_t brokenBoundary = -1;
	for (const Body::id_t id : kinematic)
		if (const auto& b = Body::byId(id, scene); b && !(b->state->pos.allFinite() && b->state->vel.allFinite() && b->state->angVel.allFinite())) {
			brokenBoundary = id;
			finite         = false;
			break;
		}
	// what moving bodies and capillary attraction (minus its booked work, P21) have put in
	const InteractionEnergy interactions = interactionEnergy();
	Real elastic = finite ? interactions.elastic : 0, work = boundaryWork - (interactions.capillary - capillaryAtReference);
	// [MPI] the check is global: every rank compares the sums over all ranks (no-op serially)
	sumOverRanks(kinetic, gravityWork, work, elastic, finite);
	kineticEnergy = kinetic;
	energyIn      = startEnergy + std::max<Real>(0, gravityWork + work);
	// E5: the tolerance scales with the most the scene has held, not with what is in it now: a body
	// that bounces back up returns its energy to gravity, and the leapfrog's energy error of its
	// bounce (a fraction of the bounce's energy) is then compared with almost nothing
	peakEnergyIn  = std::max(peakEnergyIn, energyIn);
	std::string what;
	Real        mechanical = 0;
	if (finite) {
		mechanical = kinetic + elastic;
		// a NaN on either side fails every comparison: it is a stop of its own, not an excess
		if (!std::isfinite(mechanical) || !std::isfinite(energyIn))
			what = "the energy balance is not a finite number: the kinetic + elastic energy is " + fmt(mechanical)
			        + " J against what the scene had at step " + std::to_string(referenceIter) + " plus the work of gravity and moving bodies since, "
			        + fmt(energyIn) + " J (a NaN or inf velocity, position or force)";
		else if (mechanical > energyIn + (energyMargin - 1) * peakEnergyIn + energyFloor)
			what = "the kinetic + elastic energy " + fmt(mechanical) + " J exceeds what the scene had at step " + std::to_string(referenceIter)
			        + " plus the work of gravity and moving bodies since, " + fmt(energyIn) + " J, by more than " + fmt(energyMargin - 1)
			        + " × the most it held since (" + fmt(peakEnergyIn) + " J)";
	}
	if (finite && what.empty()) {
		lastSlack = std::max<Real>(0, energyIn - mechanical); // carried over when the next run takes a new reference
		ruptured.clear();
		return;
	}
	// the body with a NaN/inf, else the one with the most kinetic energy
	Body::id_t culprit = brokenBoundary;
	Real       most    = brokenBoundary >= 0 ? std::numeric_limits<Real>::infinity() : -1;
	if (brokenBoundary >= 0)
		what = "body #" + std::to_string(brokenBoundary) + ", whose motion is prescribed (a wall, a facet or a body with blocked degrees of freedom), has a NaN or inf position or velocity";
	for (const auto& b : *scene->bodies) { // (a broken boundary is the cause of any NaN its contacts spread)
		if (brokenBoundary >= 0) break;
		if (!b || !counted(*b) || !own.body(*b)) continue;
		const State& st = *b->state;
		if (!(st.pos.allFinite() && st.vel.allFinite() && st.angVel.allFinite())) {
			what    = "body #" + std::to_string(b->getId()) + " has a NaN or inf position or velocity";
			culprit = b->getId();
			break;
		}
		if (bodyKineticEnergy(st) > most) {
			most    = bodyKineticEnergy(st);
			culprit = b->getId();
		}
	}
	// [MPI] the culprit over all ranks; its rank writes the diagnosis that every rank raises
	const int culpritRank = distributedCulprit(culprit, most);
	lastError = distributed::broadcast(scene, culpritRank, diagnose(culprit, what));
	lastError = distributed::rankLabel(scene, culpritRank) + lastError;
	// not logged here: YADE's ThreadRunner (or Python, for O.step()) prints the exception's text
	throw std::runtime_error(lastError);
}

// The last step's ruptures (the law published them in the step before this call).
void ViscBridgeGuard::collectRuptures()
{
	for (const BridgeEvent& e : ViscBridgeContext::of(scene).events(scene->iter - 1))
		if (e.kind == BridgeEvent::Kind::ruptured)
			for (const Body::id_t id : { e.id1, e.id2 })
				ruptured.push_back({ id, e.dampingRate, e.stiffnessRate });
}

// P14 of the bodies whose bridges ruptured since the last check that passed, as if those bridges
// were still there: the state in which the run was last healthy bounds the advice too.
void ViscBridgeGuard::boundWithRuptured(bool implicit)
{
	std::vector<Real> damping(scene->bodies->size(), 0), stiffness(scene->bodies->size(), 0);
	for (const Ruptured& r : ruptured) {
		const shared_ptr<Body>& b = Body::byId(r.id, scene);
		if (!b || !b->isDynamic() || !(b->state->mass > 0) || 3 * static_cast<size_t>(r.id) >= bound.summed.size()) continue;
		damping[r.id] += implicit ? 0 : r.damping;
		stiffness[r.id] += r.stiffness;
		const Real limit = bound.bodyLimit(r.id, damping[r.id], stiffness[r.id]);
		if (limit < bound.combined) bound.combined = limit, bound.criticalBody = r.id;
	}
}

std::string ViscBridgeGuard::safeStepAdvice(bool implicit, bool washino)
{
	std::ostringstream msg;
	msg.precision(4);
	const Real safe = 0.5 * bound.combined;
	if (!(safe > 0) || !std::isfinite(safe)) {
		msg << " No time step can be recommended: nothing in the current contacts bounds it.";
	} else if (safe >= scene->dt) {
		msg << " The time step dt = " << scene->dt << " s is already below half the rigorous bound P14 of the current contacts (" << safe
		    << " s), which guarantees stability, so a smaller dt is not the remedy: "
		    << (washino ? "the gain is likely the tangential model's (see above)."
		                : "look for energy put in from outside the bound (velocities or positions set between steps: call rebaseline() after "
		                  "such a change; an engine or PyRunner that sets velocities).");
	} else {
		// P14 is rigorous, so half of it is safe whatever the network; the stepper's spectral limit
		// (physics.md §7) is usually larger, which is why it is named as the better remedy
		msg << " A safe dt for the current contacts: " << safe << " s (half the rigorous bound P14"
		    << (ruptured.empty() ? "" : ", counting the bridges ruptured since the last check") << "; "
		    << (implicit ? "implicit viscous forces: collision bound only)."
		                 : "ViscBridgeTimeStepper sets dt from the live network's own limit, at least as high; or use "
		                   "integration='implicit' to lift the viscous limit).");
	}
	return msg.str();
}

std::string ViscBridgeGuard::diagnose(Body::id_t worst, const std::string& what)
{
	std::ostringstream msg;
	msg.precision(4);
	msg << "ViscBridgeGuard stopped the run at step " << scene->iter << " (t = " << scene->time << " s, dt = " << scene->dt << " s): " << what << ".";
	const bool implicit = viscousIntegrationIsImplicit(scene);
	const auto functors = findViscBridgeFunctors(scene);
	// a tangential model that is not dissipative can put energy in by itself (physics.md P7)
	const bool washino = functors.ip2 && !viscbridge::TangentialModels::capabilities[functors.ip2->selection.tangential].dissipative;
	bound.evaluate(scene, implicit, 0.4);
	boundWithRuptured(implicit);
	distributed::reduceTimeStepBound(scene, bound.collision, bound.viscous, bound.combined, bound.criticalBody); // [MPI] all ranks
	if (washino)
		msg << " The scene uses tangentialModel='" << functors.ip2->tangentialModel << "', which is not dissipative (physics.md P7): it can "
		    << "create kinetic energy at any time step, so this gain may be the model's rather than an unstable time step; 'slip' and "
		       "'goldman' are dissipative.";
	if (worst >= 0 && Body::byId(worst, scene)) {
		const Body& b = *Body::byId(worst, scene);
		msg << " Body #" << worst << " at " << vec(b.state->pos) << ", velocity " << vec(b.state->vel) << ".";
		// its most demanding interaction: the smallest explicit limit
		Real                  tightest = std::numeric_limits<Real>::infinity();
		const Interaction*    which    = nullptr;
		const ViscBridgePhys* phys     = nullptr;
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
				msg << "Violated: the explicit viscous pair limit dt < 2 m*/(C_n + w_t C_t) = " << 2 * tv << " s (physics.md P12, P14a).";
			else if (scene->dt > tightest)
				msg << "Violated: the pair limit 4m*/(C + sqrt(C² + 4m*k)) = " << tightest << " s (physics.md P13).";
			else if (scene->dt > bound.combined)
				msg << "dt is within this pair's limit (" << tightest << " s) but above the network bound P14 of the current contacts ("
				    << bound.combined << " s), below which stability is guaranteed.";
			else
				msg << "dt is within this pair's limit (" << tightest << " s) and the network bound P14 (" << bound.combined << " s).";
		}
	}
	msg << safeStepAdvice(implicit, washino);
	return msg.str();
}

void ViscBridgeGuard::action()
{
	// [MPI] an error found on any rank (e.g. by the law) stops every rank, with the same message
	const std::string pending = distributed::firstError(scene, ViscBridgeContext::of(scene).takePendingError());
	if (!pending.empty()) {
		lastError = pending;
		throw std::runtime_error(pending);
	}
	bool         newRun    = startsNewRun();
	const size_t signature = sceneSignature(scene) ^ distributed::ownedBodiesSignature(scene); // [MPI] bodies moved between ranks
	bool         changed   = signature != checkedSignature || scene->iter == 0;
	// [MPI] every rank takes the same branch below (a collective in one is awaited by all) and steps
	// with the same dt (no-op serially)
	agreeWithOtherRanks(changed, newRun);
	if (changed) {
		try {
			distributed::collectively(scene, [&] { validateScene(scene, true); }); // [MPI] one rank's error stops all
			warnImplausible(scene);
		} catch (const std::exception& e) {
			lastError = e.what(); // readable even where YADE's O.run(n, True) loses a first-step error
			throw;
		}
		checkedSignature = signature;
		referencePending = true;
	} else if (referencePending || rebaselineRequested) {
		if (rebaselineRequested) ++rebaselines;
		takeReference(0);
	} else {
		if (newRun) {
			takeReference(lastSlack);
			++rebaselines;
		}
		accumulateBoundaryWork(newRun);
		collectRuptures();
		if (scene->iter % iterPeriod == 0) checkEnergy();
	}
	lastCallEnd = Clock::now();
}

} // namespace yade
