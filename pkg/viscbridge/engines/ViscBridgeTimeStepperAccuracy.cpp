// ViscBridgeTimeStepper's accuracy: the error estimate of every step, the step a tolerance allows,
// and the scheme chosen per phase (physics.md §7a, A1–A5).
#include "viscbridge/engines/ViscBridgeTimeStepper.hpp"
#include "viscbridge/core/util/Validation.hpp"
#include "viscbridge/distributed/Distributed.hpp"
#include "viscbridge/yade/OrderedWetContacts.hpp"
#include "viscbridge/scene/SceneValidation.hpp"
#include "viscbridge/yade/Law2_ScGeom_ViscBridgePhys_HertzViscous.hpp"
#include "viscbridge/yade/ViscBridgeContext.hpp"
#include "viscbridge/yade/StepErrorSource.hpp"
#include <pkg/dem/ScGeom.hpp>
#include <limits>

namespace yade {

namespace vb = viscbridge;

// The step Newton just took and its error (A1): it moved each body with the forces of its start,
// F_{n−1}, held over the step; the forces now, F_n, show how they changed on the way.  A force that
// changes linearly gives the body ½Δt|F_n − F_{n−1}|/m more or less velocity than the step did (the
// trapezoidal companion of the step), and moves it by Δt times that.  Bodies the implicit solver
// holds by bridges take its filtered estimate of the same step instead (A1a).  Bodies that appear
// or vanish are not counted; a clump's force is summed by NewtonIntegrator after this engine, so a
// clump counts with its speed but without an error (not yet estimated).
vb::StepMotion ViscBridgeTimeStepper::lastStepMotion(Scene* sc)
{
	const auto            own   = distributed::ownership(sc);
	const size_t          n     = sc->bodies->size();
	const bool            valid = previousForce.size() == n && forceIter == sc->iter - 1;
	const auto*           solver   = ViscBridgeContext::findEngine<StepErrorSource>(sc);
	const bool            filtered = solver && solver->stepErrorStep() == sc->iter - 1 && solver->stepErrorCovers().size() == n;
	const Real            dt    = sc->dt;
	Real                  mass = 0, speedSq = 0, errorSq = 0, offsetSq = 0, freeSq = 0, freeDot = 0, freeAccSq = 0;
	resumeOffsets(sc);
	const auto&           offset  = ViscBridgeContext::of(sc).velocityOffset;
	auto&                 carried = ViscBridgeContext::of(sc).velocityError; // A1c
	auto&                 shifted = ViscBridgeContext::of(sc).positionError;
	Real                  carriedSq = 0, shiftedSq = 0, freshSq = 0, rawSq = 0, historySq = 0;
	const auto&           history = ViscBridgeContext::of(sc).historyError; // A1e
	const auto            finite    = [](const std::vector<Vector3r>& v, size_t id) { return id < v.size() && v[id].allFinite() ? v[id].squaredNorm() : 0.0; };
	const Vector3r        gravity = ViscBridgeContext::newtonGravity(sc);
	static const Vector3r none = Vector3r::Constant(std::numeric_limits<Real>::quiet_NaN());
	previousForce.resize(n, none);
	carried.resize(n, none), shifted.resize(n, none);
	// a bridge that formed this step adds its force at once: a jump of the model, not a change the
	// step integrated, so its bodies' force change is not an error (their next step's is)
	for (const BridgeEvent& e : ViscBridgeContext::of(sc).events(sc->iter))
		if (e.kind == BridgeEvent::Kind::formed)
			for (Body::id_t id : { e.id1, e.id2 })
				if (static_cast<size_t>(id) < n) previousForce[id] = none;
	sc->forces.sync();
	// A1c's carry of the explicit scheme (the solver carries its own bodies' errors), with the live
	// rates gathered at the first body that needs them: a dry scene never pays the pass
	const bool explicitScheme = !viscousImplicit();
	explicitCarried.clear();
	for (size_t id = 0; id < n; ++id) {
		const shared_ptr<Body>& b = (*sc->bodies)[id];
		if (!b || !b->isDynamic() || b->isClumpMember() || !own.body(*b) || distributed::isSubdomainBody(*b) || !(b->state->mass > 0)) {
			previousForce[id] = none;
			continue;
		}
		const Vector3r& f       = sc->forces.getForce(static_cast<Body::id_t>(id));
		const Real      m       = b->state->mass;
		const bool      covered = filtered && solver->stepErrorCovers()[id]; // its error is in the solver's sum
		const bool      raw     = !covered && valid && previousForce[id].allFinite();
		if (covered || raw) {
			const Vector3r dv = raw ? Vector3r(0.5 * dt * (f - previousForce[id]) / m) : Vector3r::Zero();
			mass += m;
			speedSq += m * b->state->vel.squaredNorm();
			const bool carriedByBridges = raw && explicitScheme && explicitDamping(id) > 0;
			if (carriedByBridges) stageExplicitCarry(id, dv, carried[id], shifted[id]);
			else errorSq += m * dv.squaredNorm(), rawSq += m * dv.squaredNorm();
			if (covered) historySq += m * finite(history, id);
			if (!carriedByBridges) carriedSq += m * finite(carried, id), shiftedSq += m * finite(shifted, id);
			const Vector3r o = id < offset.size() && offset[id].allFinite() ? offset[id] : Vector3r::Zero();
			offsetSq += m * o.squaredNorm();
			if (!covered && !(explicitDamping(id) > 0)) { // A4b: the offsets the next Δt changes as it is
				const Vector3r a = acceleration(*b->state, f, gravity);
				freeSq += m * o.squaredNorm(), freeDot += m * o.dot(a), freeAccSq += m * a.squaredNorm();
			}
		}
		previousForce[id] = f;
	}
	if (filtered) errorSq += solver->stepErrorSquared(), freshSq += solver->stepCarriedSquared();
	if (!explicitCarried.empty()) carryExplicit(sc, carriedSq, shiftedSq, freshSq);
	forceIter = sc->iter;
	distributed::sum(sc, { &mass, &speedSq, &errorSq, &offsetSq, &freeSq, &freeDot, &freeAccSq, &carriedSq, &shiftedSq, &freshSq, &rawSq, &historySq }); // [MPI] the same motion on every rank
	if (!(mass > 0)) return {};
	return { dt, std::sqrt(speedSq / mass), std::sqrt(errorSq / mass), std::sqrt(offsetSq / mass), freeSq / mass, freeDot / mass, freeAccSq / mass,
		 std::sqrt(carriedSq / mass), std::sqrt(shiftedSq / mass), std::sqrt(freshSq / mass), std::sqrt((rawSq + historySq) / mass) };
}

// A1c under the explicit scheme: a body its bridges damp keeps the velocity error δv of a step as a
// body of the network does: the viscous force lags the velocity it damps, which a step of the same
// size cannot undo, and the error is relaxed only as the bridges' live coefficients relax a velocity
// — through the network, as explicit Euler propagates it, ε_{n+1} = ε' − Δt M⁻¹D ε' with ε' = ε_n +
// δv_n and D the bridges' translational damping at their gaps now (P3) — except above half the
// stability limit h, where it is taken at h/(2Δt) of the change: at the limit explicit Euler's
// own 1 − z ≈ −1 would keep the top mode's alternating errors for good (the 45-sphere bed's estimate
// read 10⁴× its true error at safety 1); so scaled, the top mode's error goes to 0 and the others
// relax at least half as fast as the scheme relaxes them.
// An error the bodies a bridge ties share (a cluster's common motion) is not relaxed by it: relaxed
// per body at d, a 45-sphere bed at 1 Pa·s kept 1 % of its true error after a few µs (physics.md
// A1c).  The run's error counts the position error ξ it makes, ξ_{n+1} = ξ_n + Δt ε_{n+1}, not
// Δt|δv|.  Staged per body in lastStepMotion's loop (ε'), relaxed here with one pass over the
// interactions.
void ViscBridgeTimeStepper::stageExplicitCarry(size_t id, const Vector3r& dv, Vector3r& carried, Vector3r& shifted)
{
	if (!carried.allFinite() || !shifted.allFinite()) carried = shifted = Vector3r::Zero();
	carried += dv;
	explicitCarried.push_back({ id, dv.norm() });
}

// The staged errors relaxed by the network (above), their sums added to the step's: the carried
// velocity and position errors, and the share of the controller — δv over the steps it persists
// (A1c), at the body's own relaxation rate 1 + Δt d.
void ViscBridgeTimeStepper::carryExplicit(Scene* sc, Real& carriedSq, Real& shiftedSq, Real& freshSq)
{
	auto&        carried = ViscBridgeContext::of(sc).velocityError;
	auto&        shifted = ViscBridgeContext::of(sc).positionError;
	const size_t n       = sc->bodies->size();
	const Real   dt      = sc->dt;
	carryStaged.assign(n, 0);
	for (const auto& c : explicitCarried)
		carryStaged[c.id] = 1;
	liveDamping.assign(n, 0);
	carryChange.assign(n, Vector3r::Zero());
	// the top mode's z = λ_max Δt, 2Δt/h at the stability limit h = dtBound/safety
	const Real topMode = dtBound > 0 && std::isfinite(dtBound) ? 2 * safety * dt / dtBound : 0;
	const Real share   = std::min(Real(1), 1 / topMode);
	// in the order of the bodies' ids (OrderedWetContacts): the same estimate on any number of threads
	orderedWetContacts(sc, [](const Interaction&, const ViscBridgePhys& ph) { return ph.bridge && ph.mEff > 0; }, carryContacts);
	for (const auto& [key, I] : carryContacts) {
		const auto& ph = static_cast<const ViscBridgePhys&>(*I->phys);
		const auto id1 = static_cast<size_t>(I->getId1()), id2 = static_cast<size_t>(I->getId2());
		liveDamping[id1] += ph.cn / ph.mEff, liveDamping[id2] += ph.cn / ph.mEff;
		if (!carryStaged[id1] && !carryStaged[id2]) continue;
		const Vector3r  relative = (carryStaged[id1] ? carried[id1] : Vector3r::Zero()) - (carryStaged[id2] ? carried[id2] : Vector3r::Zero());
		const Vector3r& normal   = static_cast<const ScGeom&>(*I->geom).normal;
		const Real      along    = normal.dot(relative);
		const Vector3r  force    = ph.cn * along * normal + ph.ct * (relative - along * normal); // on body 1: minus this
		carryChange[id1] -= force, carryChange[id2] += force;
	}
	for (const auto& c : explicitCarried) {
		const Real m = (*sc->bodies)[c.id]->state->mass;
		carried[c.id] = ViscBridgeContext::relaxedOffset(carried[c.id] + dt * share * carryChange[c.id] / m);
		shifted[c.id] = ViscBridgeContext::relaxedOffset(shifted[c.id] + dt * carried[c.id]);
		carriedSq += m * carried[c.id].squaredNorm(), shiftedSq += m * shifted[c.id].squaredNorm();
		freshSq += m * std::pow(vb::persistingShare(c.dvNorm, c.dvNorm / (1 + dt * liveDamping[c.id])), 2);
	}
}

// A loaded scene's offsets, from its saved state (ViscBridgeTimeStepperState.cpp).
void ViscBridgeTimeStepper::resumeOffsets(Scene* sc)
{
	if (resumedMotion.empty()) return;
	auto& offset = ViscBridgeContext::of(sc).velocityOffset;
	offset.assign(sc->bodies->size(), Vector3r::Constant(std::numeric_limits<Real>::quiet_NaN()));
	for (size_t k = 0; k + savedMotionStride <= resumedMotion.size(); k += savedMotionStride) {
		const auto id = static_cast<size_t>(resumedMotion[k]);
		if (id < offset.size()) offset[id] = resumedVector(resumedMotion, k + 4);
	}
	std::vector<Real>().swap(resumedMotion);
	auto& context = ViscBridgeContext::of(sc);
	resumePairs(resumedErrors, sc->bodies->size(), context.velocityError, context.positionError);
	resumePairs(resumedHistory, sc->bodies->size(), context.historyError, context.historyFresh);
}

// Per body, the two vectors of the saved (id, a, b) records; NaN (not started) for the others.
void ViscBridgeTimeStepper::resumePairs(std::vector<Real>& saved, size_t bodies, std::vector<Vector3r>& a, std::vector<Vector3r>& b)
{
	a.assign(bodies, Vector3r::Constant(std::numeric_limits<Real>::quiet_NaN()));
	b.assign(bodies, Vector3r::Constant(std::numeric_limits<Real>::quiet_NaN()));
	for (size_t k = 0; k + savedErrorStride <= saved.size(); k += savedErrorStride) {
		const auto id = static_cast<size_t>(saved[k]);
		if (id < bodies) a[id] = resumedVector(saved, k + 1), b[id] = resumedVector(saved, k + 4);
	}
	std::vector<Real>().swap(saved);
}

// The explicit bridges' damping rate of body `id` (P14's row sum, from the last full update and
// the bridges formed since; 0 under the implicit scheme).
Real ViscBridgeTimeStepper::explicitDamping(size_t id) const
{
	return (3 * id + 2 < bound.summed.size() ? bound.summed[3 * id + 2] : 0) + (id < addedDamping.size() ? addedDamping[id] : 0);
}

// The acceleration a leapfrog step gives a body from force f: gravity added as Newton adds it, none
// along blocked directions.
Vector3r ViscBridgeTimeStepper::acceleration(const State& st, const Vector3r& f, const Vector3r& gravity)
{
	Vector3r a = f / st.mass + gravity;
	for (int d = 0; d < 3; ++d)
		if (st.blockedDOFs & State::axisDOF(d, false)) a[d] = 0;
	return a;
}

// A1b: YADE's leapfrog gives a body v += Δt_n·a_n and moves it by Δt_n times that velocity; its
// velocity stands for the middle of the step.  The run's initial velocities stand for its start
// (half a step early), and when Δt changes from Δt_{n−1} to Δt_n the middles move by ½(Δt_n −
// Δt_{n−1}) while the velocity does not: each adds ½(Δt_n − Δt_{n−1})·a to an offset every later
// step moves the body by (a free fall at a constant Δt: ½Δt·g·t, ½g Σ Δt_n² as Δt varies).  The
// offset is signed: shrinking Δt takes back what growing it gave.  a is the force the stepper sees
// (after the interaction loop, without the implicit viscous forces: backward Euler's own motion is
// A1's) plus gravity.  A body the explicit bridges damp (its force holds their lagged viscous one)
// gains none, and its offset relaxes at their rate d as a velocity would, by 1/(1 + Δt d) per step
// (the implicit solver relaxes its bodies' offsets with the whole network).  Called once the
// step's Δt is set.
void ViscBridgeTimeStepper::advanceOffsets(Scene* sc, Real dtBefore)
{
	auto&           offset  = ViscBridgeContext::of(sc).velocityOffset;
	auto&           carried = ViscBridgeContext::of(sc).velocityError; // A1c: the implicit solver adds to it, explicit bridges relax it
	const size_t    n       = sc->bodies->size();
	static const Vector3r unstarted = Vector3r::Constant(std::numeric_limits<Real>::quiet_NaN());
	auto&           shifted = ViscBridgeContext::of(sc).positionError;
	if (restartOffsets) {
		offset.clear(), carried.clear(), shifted.clear(), restartOffsets = false;
		ViscBridgeContext::of(sc).historyError.clear(), ViscBridgeContext::of(sc).historyFresh.clear();
	}
	shifted.resize(n, unstarted);
	offset.resize(n, unstarted);
	carried.resize(n, unstarted);
	const Vector3r gravity = ViscBridgeContext::newtonGravity(sc);
	for (size_t id = 0; id < n; ++id) {
		const bool counted = id < previousForce.size() && previousForce[id].allFinite() && forceIter == sc->iter;
		if (!counted) { // not a body the estimate counts this step (a clump, a fixed or a new one)
			offset[id] = carried[id] = shifted[id] = unstarted;
			continue;
		}
		const Real damping = explicitDamping(id);
		if (damping > 0) { // (its carried error, A1c, is relaxed with the step's own error: carryExplicit)
			offset[id] = offset[id].allFinite() ? ViscBridgeContext::relaxedOffset(offset[id] / (1 + sc->dt * damping)) : Vector3r::Zero();
			continue;
		}
		const Vector3r a = acceleration(*(*sc->bodies)[id]->state, previousForce[id], gravity);
		offset[id] = offset[id].allFinite() ? Vector3r(offset[id] + 0.5 * (sc->dt - dtBefore) * a) : Vector3r(0.5 * sc->dt * a);
	}
}

Real ViscBridgeTimeStepper::accuracyStep(Scene* sc)
{
	accuracyEstimate.record(lastStepMotion(sc));
	if (accuracy > 0) accuracyEstimate.tighten(accuracy);
	errorTightening = accuracyEstimate.tighteningNow();
	errorEstimate = accuracyEstimate.runError();
	stepError     = accuracyEstimate.stepError();
	dtAccuracy    = accuracy > 0 ? accuracyEstimate.allowedStep(sc->dt, accuracy, dtBound) /* the last full update's limit */ : std::numeric_limits<Real>::infinity();
	return dtAccuracy; // before the first step is known: firstStep() of the limit, in computeTimeStep
}

// The limit of the scheme that is not running, from P14 (rigorous: at most its spectral limit, so
// a switch is made on the safe side), without the safety factor.
Real ViscBridgeTimeStepper::otherSchemeLimit(Scene* sc, bool runningImplicit)
{
	otherBound.evaluate(sc, !runningImplicit, rayleighFraction);
	return std::min(otherBound.combined, otherBound.rayleigh);
}

void ViscBridgeTimeStepper::requireSchemeEngines(Scene* sc) const
{
	if (!findViscBridgeFunctors(sc).law || !ViscBridgeContext::hasEngine(sc, "ViscBridgeImplicitSolver"))
		throw std::invalid_argument("ViscBridgeTimeStepper.autoIntegration=True needs Law2_ScGeom_ViscBridgePhys_HertzViscous in an "
		                            "InteractionLoop and ViscBridgeImplicitSolver in O.engines (viscbridge.engines(integration='auto') "
		                            "adds both); set autoIntegration=False or add them.");
	if (distributed::active(sc))
		throw std::invalid_argument("ViscBridgeTimeStepper.autoIntegration=True is not available under yade.mpy; allowed there: False "
		                            "(choose Law2_ScGeom_ViscBridgePhys_HertzViscous.integration yourself).");
}

void ViscBridgeTimeStepper::refuseAccuracyOverRanks(Scene* sc) const
{
	// The estimate's carried parts (A1b offsets, A1c/A1e carried and history errors) travel through
	// the bridges, and the solver does not yet exchange them between ranks: without them the
	// estimate would be smaller than the serial run's, and the step larger, without a word.
	if (distributed::active(sc))
		throw std::invalid_argument("ViscBridgeTimeStepper.accuracy=" + viscbridge::formatValue(accuracy)
		                            + " is not available under yade.mpy (its error estimate is not yet carried across the ranks); "
		                              "allowed there: accuracy=0 (the stability limit, with the safety factor). To know what a "
		                              "tolerance costs, run the scene or a smaller one with accuracy in one process (threads: -j) "
		                              "and fix the step it finds with maxDt.");
}

// A5, decided after this step's dt is set (the law has already run this step with the scheme in
// use; the other one takes over from the next step, whose full update computes its limit).
void ViscBridgeTimeStepper::chooseScheme(Scene* sc, Real accuracyStepNow)
{
	const bool implicit = viscousImplicit();
	scheme              = implicit ? "implicit" : "explicit";
	if (!autoIntegration || !std::isfinite(dtBound)) return;
	// decide on fresh limits only (the first time at once: a scene loaded or autoIntegration just
	// set), and keep a scheme for minSchemeSteps (a transient of the error estimate does not send
	// the run back and forth)
	if ((lastSwitchIter >= 0 && sc->iter - lastSwitchIter < minSchemeSteps) || (lastUpdateIter != sc->iter && decided)) return;
	requireSchemeEngines(sc);
	decided = true;
	const Real other         = safety * otherSchemeLimit(sc, implicit);
	const Real explicitLimit = implicit ? other : dtBound, implicitLimit = implicit ? dtBound : other;
	if (vb::implicitIsCheaper(implicit, accuracyStepNow, explicitLimit, implicitLimit, implicitCost) == implicit) return;
	chosenScheme   = static_cast<int>(implicit ? vb::Integration::explicitEuler : vb::Integration::implicitEuler); // the law reads it from the next step
	lastSwitchIter = sc->iter;
	lastUpdateIter = -1; // the other operator: a full update at the next step
	forceIter      = -1; // the forces the stepper sees gain or lose the viscous ones: no error from that change
	modeById.clear();
	++schemeSwitches;
}

} // namespace yade
